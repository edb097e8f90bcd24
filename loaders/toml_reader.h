// Reading a TOML file with messages a user can act on: every error names the file, the line and column of the
// key or value, what was expected and what was found; a misspelt key gets a near-miss suggestion ("did you
// mean ...?"); values are read with their types and ranges checked; tables are checked against the keys they
// take. Internal to the loaders (it exposes toml++ types): loaders/scene_file.cpp reads the scene schema with it.
#pragma once

#include "tracer/core/errors.h"
#include "tracer/core/source_location.h"

#include <fmt/format.h>
#include <glm/glm.hpp>
#include <toml++/toml.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <climits>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace terracast::toml_reader {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kFloatMax = std::numeric_limits<float>::max();
constexpr size_t kQuotedCharsMax = 60;     // user text quoted in a message is cut after this many bytes

// ---- Text in messages ----

// `text` on one line: control characters escaped, and cut at a UTF-8 boundary after `maxBytes` bytes.
std::string printable(std::string_view text, size_t maxBytes = kQuotedCharsMax);

// A key as messages quote it.
std::string quoteKey(std::string_view key);

// A string value as messages quote it: in double quotes, escaped, cut when long.
std::string quoteString(std::string_view text);

// Quoted strings separated by commas.
std::string quoteAll(std::span<const std::string> words);

// What a TOML node is, with its article, for "found ..." phrases.
std::string describeType(const toml::node& node);

// ---- Before the parser ----

// Where `text` nests deeper than `maxDepth` levels, counting open arrays and inline tables, table headers'
// brackets and the parts of a dotted key (a.b.c is three): toml++ recurses once per level, so a file of a few
// hundred kilobytes could otherwise exhaust the stack. None when the text stays within the bound. A lexical
// scan, not a parse: it skips strings and comments and errs towards counting more (a float's dot counts as one).
std::optional<SourceLocation> findExcessiveNesting(std::string_view text, int maxDepth);

// ---- Near misses ----

// " (did you mean 'radius'?)" when a candidate is close to `word`, else "".
std::string didYouMean(std::string_view word, std::span<const std::string> candidates, bool asKey);

// ---- Value ranges ----

// An interval of accepted numbers; infinite ends are open and not written in messages.
struct Range {
    double lo = -kInf;
    double hi = kInf;
    bool loClosed = true;
    bool hiClosed = true;

    bool contains(double v) const {
        return (loClosed ? v >= lo : v > lo) && (hiClosed ? v <= hi : v < hi);
    }
    // " > 0", " >= 0", " in (0, 180)", or "" for every number.
    std::string describe() const {
        if (lo == -kInf && hi == kInf) return "";
        if (hi == kInf) return fmt::format(" {} {:g}", loClosed ? ">=" : ">", lo);
        if (lo == -kInf) return fmt::format(" {} {:g}", hiClosed ? "<=" : "<", hi);
        return fmt::format(" in {}{:g}, {:g}{}", loClosed ? '[' : '(', lo, hi, hiClosed ? ']' : ')');
    }
};

constexpr Range kAnyNumber{};
constexpr Range kNonNegative{0.0, kInf, true, true};
constexpr Range kPositive{0.0, kInf, false, true};
// Coordinates and lengths in metres: a scene fits in a cube a million kilometres wide, where double precision
// still resolves a micrometre and no product of two coordinates overflows.
constexpr Range kCoordinate{-1e9, 1e9, true, true};
constexpr Range kLength{0.0, 1e9, false, true};

// ---- Locations and errors ----

SourceLocation locationOf(const toml::source_region& region, SourceLocation fallback);

// The TOML file being parsed: its name for messages, the folder its relative paths start from, and whether
// its paths may lead anywhere (see resolveConfined).
class TomlFile {
public:
    TomlFile(std::string path, std::string baseDir, bool anyPath = false)
        : path_(std::move(path)), baseDir_(std::move(baseDir)), anyPath_(anyPath) {}

    [[noreturn]] void fail(SourceLocation where, const std::string& message) const {
        throw InputError(located(where, message));
    }
    // "file:line:column: message", as errors and warnings about the file read.
    std::string located(SourceLocation where, const std::string& message) const {
        return fmt::format("{}:{}:{}: {}", path_, where.line, where.column, message);
    }

    // A path from the file, made relative to the file's folder unless it is absolute.
    std::string resolve(const std::string& path) const {
        if (path.starts_with("/vsi")) return path;  // GDAL virtual file systems keep their exact spelling
        const std::filesystem::path p(path);
        if (p.is_absolute() || baseDir_.empty()) return p.lexically_normal().string();
        return (std::filesystem::path(baseDir_) / p).lexically_normal().string();
    }

    // A path the file names for `key` (at `where`), resolved as above and confined to the file's folder unless
    // any path is allowed: GDAL virtual and network paths and absolute paths are refused, and so is a relative
    // path that leads out of the folder (after "..", and symbolic links, are followed). A file from elsewhere
    // may then neither read nor write outside its own folder, nor reach a network. `flag` names the option
    // that lifts the rule.
    std::string resolveConfined(SourceLocation where, std::string_view key, const std::string& path,
                                const char* flag) const;

private:
    std::string path_;
    std::string baseDir_;
    bool anyPath_ = false;
};

// A keyword accepted by a key, and the value it stands for.
template <typename E>
struct Choice {
    std::string_view name;
    E value;
};

template <typename E>
std::vector<std::string> choiceNames(std::span<const Choice<E>> choices) {
    std::vector<std::string> names;
    for (const auto& c : choices) names.emplace_back(c.name);
    return names;
}

template <typename E>
std::string_view choiceName(std::span<const Choice<E>> choices, E value) {
    for (const auto& c : choices)
        if (c.value == value) return c.name;
    return "";
}

// One table of the file, with typed, range-checked access to its keys. Every reader returns nothing
// when the key is absent and throws InputError at the value's location when it is malformed.
class TableReader {
public:
    TableReader(const TomlFile& file, const toml::table& table, std::string label, SourceLocation fallback)
        : file_(file), table_(table), label_(std::move(label)), where_(locationOf(table.source(), fallback)) {}

    const std::string& label() const { return label_; }
    SourceLocation where() const { return where_; }
    bool has(std::string_view key) const { return table_.contains(key); }
    const toml::node* node(std::string_view key) const { return table_.get(key); }

    [[noreturn]] void fail(SourceLocation where, const std::string& message) const { file_.fail(where, message); }
    std::string located(SourceLocation where, const std::string& message) const { return file_.located(where, message); }

    SourceLocation keyWhere(std::string_view key) const {
        for (auto&& [k, v] : table_)
            if (k.str() == key) return locationOf(k.source(), locationOf(v.source(), where_));
        return where_;
    }
    SourceLocation valueWhere(std::string_view key) const {
        const toml::node* n = table_.get(key);
        return n ? whereOf(*n) : where_;
    }
    SourceLocation whereOf(const toml::node& n) const { return locationOf(n.source(), where_); }

    // The table's keys in the order they were written.
    std::vector<std::pair<std::string, SourceLocation>> keysInOrder() const {
        std::vector<std::pair<std::string, SourceLocation>> keys;
        for (auto&& [k, v] : table_) keys.emplace_back(std::string(k.str()), locationOf(k.source(), whereOf(v)));
        std::stable_sort(keys.begin(), keys.end(), [](const auto& a, const auto& b) {
            return std::pair(a.second.line, a.second.column) < std::pair(b.second.line, b.second.column);
        });
        return keys;
    }

    // Refuses the table, at its header, when it lacks `key`.
    void require(std::string_view key, const std::string& subject) const {
        if (!has(key)) fail(where_, fmt::format("missing required key {} {}", quoteKey(key), subject));
    }

    // A number in `range`; TOML integers are accepted where numbers are expected.
    double numberFrom(const toml::node& n, const std::string& name, Range range) const {
        double value = 0.0;
        if (const auto* i = n.as_integer()) value = static_cast<double>(i->get());
        else if (const auto* f = n.as_floating_point()) value = f->get();
        else fail(whereOf(n), fmt::format("{}: expected a number{}, found {}", name, range.describe(), describeType(n)));
        if (!std::isfinite(value))
            fail(whereOf(n), fmt::format("{}: expected a finite number{}, found {}", name, range.describe(), value));
        if (!range.contains(value))
            fail(whereOf(n), fmt::format("{}: expected a number{}, found {}", name, range.describe(), value));
        return value;
    }

    std::optional<double> number(std::string_view key, Range range = kAnyNumber) const {
        const toml::node* n = node(key);
        if (!n) return std::nullopt;
        return numberFrom(*n, std::string(key), range);
    }

    // A number stored in single precision: also refuses magnitudes a float cannot hold.
    std::optional<float> singleNumber(std::string_view key, Range range = kAnyNumber) const {
        const toml::node* n = node(key);
        if (!n) return std::nullopt;
        return toSingle(*n, std::string(key), numberFrom(*n, std::string(key), range));
    }

    std::optional<int64_t> integer(std::string_view key, int64_t lo, int64_t hi) const {
        const toml::node* n = node(key);
        if (!n) return std::nullopt;
        const std::string expected = hi == std::numeric_limits<int64_t>::max()
                                         ? fmt::format("an integer >= {}", lo)
                                         : fmt::format("an integer in {}..{}", lo, hi);
        const auto* i = n->as_integer();
        if (!i) fail(whereOf(*n), fmt::format("{}: expected {}, found {}", key, expected, describeType(*n)));
        if (i->get() < lo || i->get() > hi)
            fail(whereOf(*n), fmt::format("{}: expected {}, found {}", key, expected, i->get()));
        return i->get();
    }

    std::optional<bool> boolean(std::string_view key) const {
        const toml::node* n = node(key);
        if (!n) return std::nullopt;
        const auto* b = n->as_boolean();
        if (!b) fail(whereOf(*n), fmt::format("{}: expected true or false, found {}", key, describeType(*n)));
        return b->get();
    }

    std::optional<std::string> string(std::string_view key) const {
        const toml::node* n = node(key);
        if (!n) return std::nullopt;
        const auto* s = n->as_string();
        if (!s) fail(whereOf(*n), fmt::format("{}: expected a string, found {}", key, describeType(*n)));
        return s->get();
    }

    std::optional<std::string> nonEmptyString(std::string_view key) const {
        auto s = string(key);
        if (s && s->empty()) fail(valueWhere(key), fmt::format("{}: expected a non-empty string, found \"\"", key));
        return s;
    }

    // A file path: not empty, and without control characters. The system would see only the part before a NUL;
    // a newline or a tab makes a name that breaks every script that lists the folder, and a scene file may come
    // from anyone.
    std::optional<std::string> path(std::string_view key) const {
        auto s = nonEmptyString(key);
        if (!s) return s;
        for (const char c : *s)
            if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f)
                fail(valueWhere(key),
                     fmt::format("{}: expected a file path, found a string with a control character (code {})", key,
                                 static_cast<int>(static_cast<unsigned char>(c))));
        return s;
    }

    // One of a fixed set of keywords, with a near-miss suggestion when the value is not among them.
    template <typename E>
    std::optional<E> choice(std::string_view key, std::span<const Choice<E>> choices) const {
        const auto text = string(key);
        if (!text) return std::nullopt;
        for (const auto& c : choices)
            if (c.name == *text) return c.value;
        const auto names = choiceNames(choices);
        fail(valueWhere(key), fmt::format("{}: expected one of {}, found {}{}", key, quoteAll(names),
                                          quoteString(*text), didYouMean(*text, names, false)));
    }

    // Three numbers [x, y, z] in `range` each.
    std::optional<glm::dvec3> vector3(std::string_view key, Range range = kCoordinate,
                                      std::string_view form = "[x, y, z]") const {
        const toml::node* n = node(key);
        if (!n) return std::nullopt;
        return vector3From(*n, std::string(key), range, form);
    }

    // A direction: three numbers, not all zero.
    std::optional<glm::dvec3> direction(std::string_view key) const {
        const auto d = vector3(key);
        if (d && *d == glm::dvec3(0.0))
            fail(valueWhere(key), fmt::format("{}: expected a non-zero direction, found [0, 0, 0]", key));
        return d;
    }

    // An RGB triple [r, g, b] in `range`, or with `scalarAllowed` one number for all three channels.
    std::optional<glm::vec3> rgb(std::string_view key, Range range, bool scalarAllowed) const {
        const toml::node* n = node(key);
        if (!n) return std::nullopt;
        const std::string name(key);
        if (scalarAllowed && (n->is_integer() || n->is_floating_point()))
            return glm::vec3(toSingle(*n, name, numberFrom(*n, name, range)));
        if (scalarAllowed && !n->is_array())
            fail(whereOf(*n), fmt::format("{}: expected a number or an array of 3 numbers [r, g, b], found {}", key,
                                          describeType(*n)));
        const glm::dvec3 v = vector3From(*n, name, range, "[r, g, b]");
        glm::vec3 out;
        for (int c = 0; c < 3; ++c)
            out[c] = toSingle(*n->as_array()->get(static_cast<size_t>(c)), fmt::format("{}[{}]", key, c), v[c]);
        return out;
    }

    // A list of points [[x, y, z], ...].
    std::optional<std::vector<glm::dvec3>> points(std::string_view key) const {
        const toml::node* n = node(key);
        if (!n) return std::nullopt;
        const auto* array = n->as_array();
        if (!array)
            fail(whereOf(*n), fmt::format("{}: expected an array of points [[x, y, z], ...], found {}", key,
                                          describeType(*n)));
        std::vector<glm::dvec3> result;
        for (size_t i = 0; i < array->size(); ++i)
            result.push_back(vector3From(*array->get(i), fmt::format("{}[{}]", key, i), kCoordinate, "[x, y, z]"));
        return result;
    }

    // Two numbers [a, b] with a <= b.
    std::optional<std::array<double, 2>> orderedPair(std::string_view key, std::string_view form) const {
        const toml::node* n = node(key);
        if (!n) return std::nullopt;
        const auto* array = n->as_array();
        if (!array || array->size() != 2)
            fail(whereOf(*n), fmt::format("{}: expected an array of 2 numbers {}, found {}", key, form,
                                          foundArray(*n)));
        const double a = numberFrom(*array->get(0), fmt::format("{}[0]", key), kAnyNumber);
        const double b = numberFrom(*array->get(1), fmt::format("{}[1]", key), kAnyNumber);
        if (a > b) fail(whereOf(*n), fmt::format("{}: expected {} in increasing order, found [{}, {}]", key, form, a, b));
        return std::array<double, 2>{a, b};
    }

private:
    // "an array of 2 values" for arrays, the type otherwise.
    static std::string foundArray(const toml::node& n) {
        const auto* array = n.as_array();
        if (!array) return describeType(n);
        return fmt::format("an array of {} value{}", array->size(), array->size() == 1 ? "" : "s");
    }

    glm::dvec3 vector3From(const toml::node& n, const std::string& name, Range range, std::string_view form) const {
        const auto* array = n.as_array();
        if (!array || array->size() != 3)
            fail(whereOf(n), fmt::format("{}: expected an array of 3 numbers {}, found {}", name, form, foundArray(n)));
        glm::dvec3 v;
        for (int c = 0; c < 3; ++c) v[c] = numberFrom(*array->get(static_cast<size_t>(c)), fmt::format("{}[{}]", name, c), range);
        return v;
    }

    float toSingle(const toml::node& n, const std::string& name, double value) const {
        if (std::abs(value) > kFloatMax)
            fail(whereOf(n), fmt::format("{}: expected a number of magnitude at most {:.3g}, found {}", name,
                                         kFloatMax, value));
        return static_cast<float>(value);
    }

    const TomlFile& file_;
    const toml::table& table_;
    std::string label_;
    SourceLocation where_;
};

// ---- Schemas ----

// A key a table takes and the types (or sky models) that take it; none listed: every type.
struct KeyRule {
    std::string_view key;
    std::vector<std::string_view> types;
};

// Refuses, in the order they were written, keys the table's type does not take: keys of another type name
// the types that take them; other keys get a near-miss suggestion among the keys this type takes.
void checkKeys(const TableReader& table, std::span<const KeyRule> rules, std::string_view type,
               const std::string& subject);

// Before `type` is known: a key no type takes that is a near miss of the missing `required` key is reported
// as the slip it probably is, rather than as a missing key.
void refuseMisspeltKey(const TableReader& table, std::span<const KeyRule> rules, std::string_view required);

// The choices of an enumeration that names its own values (surface methods, sample patterns, pixel filters):
// the tracer's own lists, so the scene file and the tracer cannot drift apart. The names have static storage.
template <typename E>
std::vector<Choice<E>> namedChoices(std::span<const E> values, const char* (*name)(E)) {
    std::vector<Choice<E>> choices;
    for (const E v : values) choices.push_back({name(v), v});
    return choices;
}

}  // namespace terracast::toml_reader
