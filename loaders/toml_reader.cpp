#include "loaders/toml_reader.h"

#include "tracer/core/text.h"

#include <cctype>

namespace terracast::toml_reader {

std::string printable(std::string_view text, size_t maxBytes) { return escapeControls(text, maxBytes); }

std::string quoteKey(std::string_view key) { return fmt::format("'{}'", printable(key)); }

std::string quoteString(std::string_view text) {
    std::string escaped;
    for (const char c : text) {
        if (c == '"' || c == '\\') escaped += '\\';
        escaped += c;
    }
    return fmt::format("\"{}\"", printable(escaped));
}

std::string quoteAll(std::span<const std::string> words) {
    std::string out;
    for (size_t i = 0; i < words.size(); ++i) out += (i == 0 ? "" : ", ") + quoteString(words[i]);
    return out;
}

std::string describeType(const toml::node& node) {
    switch (node.type()) {
        case toml::node_type::string: return "a string";
        case toml::node_type::integer: return "an integer";
        case toml::node_type::floating_point: return "a floating-point number";
        case toml::node_type::boolean: return "a boolean";
        case toml::node_type::array: return node.is_array_of_tables() ? "an array of tables" : "an array";
        case toml::node_type::table: return "a table";
        case toml::node_type::date: return "a date";
        case toml::node_type::time: return "a time";
        case toml::node_type::date_time: return "a date-time";
        case toml::node_type::none: break;
    }
    return "nothing";
}

std::string didYouMean(std::string_view word, std::span<const std::string> candidates, bool asKey) {
    const auto best = nearMiss(word, candidates);
    if (!best) return "";
    return fmt::format(" (did you mean {}?)", asKey ? quoteKey(*best) : quoteString(*best));
}

SourceLocation locationOf(const toml::source_region& region, SourceLocation fallback) {
    if (region.begin.line == 0) return fallback;
    const auto clamp = [](toml::source_index i) { return static_cast<int>(std::min<toml::source_index>(i, INT_MAX)); };
    return {clamp(region.begin.line), clamp(region.begin.column)};
}

void checkKeys(const TableReader& table, std::span<const KeyRule> rules, std::string_view type,
               const std::string& subject) {
    std::vector<std::string> taken;
    for (const auto& rule : rules)
        if (rule.types.empty() || std::find(rule.types.begin(), rule.types.end(), type) != rule.types.end())
            taken.emplace_back(rule.key);
    for (const auto& [key, where] : table.keysInOrder()) {
        if (std::find(taken.begin(), taken.end(), key) != taken.end()) continue;
        const auto rule = std::find_if(rules.begin(), rules.end(), [&k = key](const KeyRule& r) { return r.key == k; });
        if (rule != rules.end()) {
            const std::vector<std::string> owners(rule->types.begin(), rule->types.end());
            table.fail(where, fmt::format("key {} does not apply to {} (only to {})", quoteKey(key), subject,
                                          quoteAll(owners)));
        }
        table.fail(where, fmt::format("unknown key {} in {}{}", quoteKey(key), table.label(),
                                      didYouMean(key, taken, true)));
    }
}

void refuseMisspeltKey(const TableReader& table, std::span<const KeyRule> rules, std::string_view required) {
    const std::vector<std::string> wanted{std::string(required)};
    for (const auto& [key, where] : table.keysInOrder()) {
        const bool known =
            std::any_of(rules.begin(), rules.end(), [&k = key](const KeyRule& r) { return r.key == k; });
        if (!known && nearMiss(key, wanted))
            table.fail(where, fmt::format("unknown key {} in {}{}", quoteKey(key), table.label(),
                                          didYouMean(key, wanted, true)));
    }
}

std::string TomlFile::resolveConfined(SourceLocation where, std::string_view key, const std::string& path,
                                     const char* flag) const {
    if (anyPath_) return resolve(path);
    const std::string quoted = fmt::format("\"{}\"", printable(path, std::string::npos));
    if (path.starts_with("/vsi") || path.find("://") != std::string::npos)
        fail(where, fmt::format("{}: {} is a GDAL virtual or network path; a scene file may name only files in its "
                                "own folder unless {} is given",
                                key, quoted, flag));
    if (std::filesystem::path(path).is_absolute())
        fail(where, fmt::format("{}: {} is an absolute path; a scene file may name only files in its own folder "
                                "unless {} is given",
                                key, quoted, flag));
    const std::string resolved = resolve(path);
    std::error_code ec;
    // Absolute first: weakly_canonical leaves a relative path relative when no part of it exists yet.
    const auto base = std::filesystem::weakly_canonical(
        std::filesystem::absolute(baseDir_.empty() ? std::filesystem::path(".") : std::filesystem::path(baseDir_)), ec);
    const auto target = ec ? std::filesystem::path()
                           : std::filesystem::weakly_canonical(std::filesystem::absolute(resolved), ec);
    const auto inside = [&] {
        auto b = base.begin(), t = target.begin();
        for (; b != base.end(); ++b, ++t)
            if (t == target.end() || *b != *t) return false;
        return t != target.end();
    };
    if (ec || !inside())
        fail(where, fmt::format("{}: {} leads out of the scene file's folder{}; a scene file may name only files in "
                                "its own folder unless {} is given",
                                key, quoted, ec ? "" : " (to " + printable(target.string(), std::string::npos) + ")", flag));
    return resolved;
}

std::optional<SourceLocation> findExcessiveNesting(std::string_view text, int maxDepth) {
    int line = 1, column = 0;
    int brackets = 0;   // open [ and { outside strings
    int keyParts = 1;   // parts of the dotted key (or number) being read
    bool inKey = false; // the last thing read outside strings was a key character or a quoted key
    size_t k = 0;
    auto advance = [&](size_t n) {
        for (size_t e = std::min(text.size(), k + n); k < e; ++k) {
            if (text[k] == '\n') {
                ++line;
                column = 0;
            } else if ((static_cast<unsigned char>(text[k]) & 0xC0) != 0x80) {
                ++column;
            }
        }
    };
    auto tooDeep = [&] { return brackets + keyParts > maxDepth; };
    while (k < text.size()) {
        const char c = text[k];
        const SourceLocation here{line, column + 1};
        if (c == '#') {  // a comment, to the end of the line
            while (k < text.size() && text[k] != '\n') advance(1);
            continue;
        }
        if (c == '"' || c == '\'') {
            const std::string closing(3, c);
            const bool multi = text.substr(k, 3) == std::string_view(closing);
            const size_t open = multi ? 3 : 1;
            advance(open);
            while (k < text.size()) {
                if (c == '"' && text[k] == '\\') {
                    advance(2);
                    continue;
                }
                if (!multi && text[k] == '\n') break;  // an unterminated string: the parser will say so
                if (multi ? text.substr(k, 3) == std::string_view(closing) : text[k] == c) {
                    advance(open);
                    break;
                }
                advance(1);
            }
            inKey = true;
            continue;
        }
        if (c == '[' || c == '{') {
            ++brackets;
            keyParts = 1;
            inKey = false;
            if (tooDeep()) return here;
        } else if (c == ']' || c == '}') {
            brackets = std::max(0, brackets - 1);
            keyParts = 1;
            inKey = false;
        } else if (c == '.') {
            if (inKey) {
                ++keyParts;
                if (tooDeep()) return here;
            }
        } else if (std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '+') {
            inKey = true;
        } else if (c != ' ' && c != '\t') {
            keyParts = 1;
            inKey = false;
        }
        advance(1);
    }
    return std::nullopt;
}

}  // namespace terracast::toml_reader
