// A small JSON reader for tests that check the reports commands write: enough of RFC 8259 to parse them
// (objects, arrays, strings with simple escapes, numbers, true, false, null), throwing on anything else.
#pragma once

#include <cctype>
#include <cstdlib>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace terracast::testing {

struct JsonValue {
    enum class Type { Null, Bool, Number, String, Array, Object } type = Type::Null;
    bool boolean = false;
    double number = 0.0;
    std::string string;
    std::vector<JsonValue> array;
    std::map<std::string, JsonValue> object;
    std::vector<std::string> keys;  // object keys in the order written

    bool has(const std::string& key) const { return type == Type::Object && object.count(key) != 0; }
    // The member `key`; throws when this is not an object or lacks it.
    const JsonValue& operator[](const std::string& key) const {
        if (!has(key)) throw std::runtime_error("JSON: no key '" + key + "'");
        return object.at(key);
    }
    const JsonValue& operator[](size_t k) const { return array.at(k); }
    bool isNumber() const { return type == Type::Number; }
};

namespace detail {

class JsonParser {
public:
    explicit JsonParser(const std::string& text) : s_(text) {}
    JsonValue document() {
        JsonValue v = value();
        skip();
        if (p_ != s_.size()) fail("trailing characters");
        return v;
    }

private:
    [[noreturn]] void fail(const std::string& what) const {
        throw std::runtime_error("JSON: " + what + " at offset " + std::to_string(p_));
    }
    void skip() {
        while (p_ < s_.size() && std::isspace(static_cast<unsigned char>(s_[p_]))) ++p_;
    }
    bool take(char c) {
        skip();
        if (p_ < s_.size() && s_[p_] == c) return ++p_, true;
        return false;
    }
    void expect(char c) {
        if (!take(c)) fail(std::string("expected '") + c + "'");
    }
    bool literal(const char* word) {
        const std::string w(word);
        if (s_.compare(p_, w.size(), w) != 0) return false;
        p_ += w.size();
        return true;
    }
    std::string str() {
        expect('"');
        std::string out;
        while (p_ < s_.size() && s_[p_] != '"') {
            char c = s_[p_++];
            if (c == '\\') {
                if (p_ >= s_.size()) fail("bad escape");
                const char e = s_[p_++];
                if (e == 'n') c = '\n';
                else if (e == 't') c = '\t';
                else if (e == 'u') {
                    if (p_ + 4 > s_.size()) fail("bad escape");
                    c = char(std::stoi(s_.substr(p_, 4), nullptr, 16));
                    p_ += 4;
                } else c = e;
            }
            out += c;
        }
        expect('"');
        return out;
    }
    JsonValue value() {
        skip();
        if (p_ >= s_.size()) fail("unexpected end");
        JsonValue v;
        const char c = s_[p_];
        if (c == '{') {
            ++p_;
            v.type = JsonValue::Type::Object;
            if (take('}')) return v;
            do {
                skip();
                std::string key = str();
                expect(':');
                if (v.object.count(key)) fail("duplicate key '" + key + "'");
                v.keys.push_back(key);
                v.object[key] = value();
            } while (take(','));
            expect('}');
        } else if (c == '[') {
            ++p_;
            v.type = JsonValue::Type::Array;
            if (take(']')) return v;
            do v.array.push_back(value());
            while (take(','));
            expect(']');
        } else if (c == '"') {
            v.type = JsonValue::Type::String;
            v.string = str();
        } else if (literal("true")) {
            v.type = JsonValue::Type::Bool;
            v.boolean = true;
        } else if (literal("false")) {
            v.type = JsonValue::Type::Bool;
        } else if (literal("null")) {
            v.type = JsonValue::Type::Null;
        } else {
            const char* begin = s_.c_str() + p_;
            char* end = nullptr;
            v.number = std::strtod(begin, &end);
            if (end == begin) fail("unexpected character");
            v.type = JsonValue::Type::Number;
            p_ += size_t(end - begin);
        }
        return v;
    }

    const std::string& s_;
    size_t p_ = 0;
};

}  // namespace detail

// Parses a whole JSON document; throws std::runtime_error naming the offset of the first problem.
inline JsonValue parseJson(const std::string& text) { return detail::JsonParser(text).document(); }

}  // namespace terracast::testing
