#include "base/case_file.hpp"

#include "proto/case.pb.h"

#include <google/protobuf/io/tokenizer.h>
#include <google/protobuf/text_format.h>

#include <sys/stat.h>

#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <limits>
#include <map>
#include <set>
#include <sstream>

namespace undex {

namespace pb = google::protobuf;

namespace {

struct JsonMember;

// A JSON value with the byte offset where it starts (for members: where the key starts).
struct JsonValue {
    enum Kind { Null, Bool, Number, String, Array, Object } kind = Null;
    long offset = 0;
    std::string text; // a number's token, a string's decoded value
    bool boolean = false;
    std::vector<JsonMember> members; // the value's offset is that of its key
    std::vector<JsonValue> elements;
};
struct JsonMember {
    std::string key;
    JsonValue value;
};

// "file:line:col" of a byte offset of text.
std::string position(const std::string& file, const std::string& text, long offset) {
    long line = 1, col = 1;
    for (long k = 0; k < offset && k < static_cast<long>(text.size()); ++k) {
        if (text[k] == '\n')
            ++line, col = 1;
        else
            ++col;
    }
    return file + ":" + std::to_string(line) + ":" + std::to_string(col);
}

// A strict JSON reader (RFC 8259): no comments, trailing commas, duplicate keys, NaN or Infinity, control
// characters in strings, or anything after the value. Nesting deeper than max_depth is refused (a case is
// about 5 deep).
class JsonReader {
  public:
    JsonReader(const std::string& text, const std::string& file) : s_(text), file_(file) {}
    JsonValue document() {
        skip_space();
        JsonValue v = value(0);
        skip_space();
        if (k_ < s_.size()) error("unexpected text after the JSON value");
        return v;
    }

  private:
    static constexpr int max_depth = 64;
    const std::string& s_;
    const std::string& file_;
    size_t k_ = 0;

    [[noreturn]] void error(const std::string& message, long at = -1) const {
        throw CaseError(position(file_, s_, at < 0 ? static_cast<long>(k_) : at) + ": " + message);
    }
    void skip_space() {
        while (k_ < s_.size() && (s_[k_] == ' ' || s_[k_] == '\t' || s_[k_] == '\n' || s_[k_] == '\r'))
            ++k_;
    }
    bool literal(const char* word) {
        const size_t n = std::strlen(word);
        if (s_.compare(k_, n, word) != 0) return false;
        k_ += n;
        return true;
    }
    JsonValue value(int depth) {
        if (depth > max_depth) error("JSON nested deeper than " + std::to_string(max_depth) + " levels");
        JsonValue v;
        v.offset = static_cast<long>(k_);
        if (k_ >= s_.size()) error("unexpected end of the file: a value is expected");
        const char c = s_[k_];
        if (c == '{') {
            v.kind = JsonValue::Object;
            object(v, depth);
        } else if (c == '[') {
            v.kind = JsonValue::Array;
            array(v, depth);
        } else if (c == '"') {
            v.kind = JsonValue::String;
            v.text = string();
        } else if (c == '-' || (c >= '0' && c <= '9')) {
            v.kind = JsonValue::Number;
            v.text = number();
        } else if (literal("true")) {
            v.kind = JsonValue::Bool, v.boolean = true;
        } else if (literal("false")) {
            v.kind = JsonValue::Bool;
        } else if (literal("null")) {
            v.kind = JsonValue::Null;
        } else {
            error(std::string("unexpected character '") + c + "': a value is expected");
        }
        return v;
    }
    void object(JsonValue& v, int depth) {
        ++k_; // {
        skip_space();
        if (k_ < s_.size() && s_[k_] == '}') {
            ++k_;
            return;
        }
        std::set<std::string> keys;
        for (;;) {
            skip_space();
            const long key_at = static_cast<long>(k_);
            if (k_ >= s_.size() || s_[k_] != '"')
                error(k_ < s_.size() && s_[k_] == '}' ? "trailing comma before '}'"
                                                      : "a key in quotes is expected");
            std::string key = string();
            if (!keys.insert(key).second) error("duplicate key '" + key + "'", key_at);
            skip_space();
            if (k_ >= s_.size() || s_[k_] != ':') error("':' is expected after the key '" + key + "'");
            ++k_;
            skip_space();
            JsonValue member = value(depth + 1);
            member.offset = key_at;
            v.members.push_back({std::move(key), std::move(member)});
            skip_space();
            if (k_ < s_.size() && s_[k_] == ',') {
                ++k_;
                continue;
            }
            if (k_ < s_.size() && s_[k_] == '}') {
                ++k_;
                return;
            }
            error("',' or '}' is expected");
        }
    }
    void array(JsonValue& v, int depth) {
        ++k_; // [
        skip_space();
        if (k_ < s_.size() && s_[k_] == ']') {
            ++k_;
            return;
        }
        for (;;) {
            skip_space();
            if (k_ < s_.size() && s_[k_] == ']') error("trailing comma before ']'");
            v.elements.push_back(value(depth + 1));
            skip_space();
            if (k_ < s_.size() && s_[k_] == ',') {
                ++k_;
                continue;
            }
            if (k_ < s_.size() && s_[k_] == ']') {
                ++k_;
                return;
            }
            error("',' or ']' is expected");
        }
    }
    static void utf8(std::string& out, unsigned cp) {
        if (cp < 0x80) {
            out += static_cast<char>(cp);
        } else if (cp < 0x800) {
            out += static_cast<char>(0xC0 | (cp >> 6));
            out += static_cast<char>(0x80 | (cp & 0x3F));
        } else if (cp < 0x10000) {
            out += static_cast<char>(0xE0 | (cp >> 12));
            out += static_cast<char>(0x80 | ((cp >> 6) & 0x3F));
            out += static_cast<char>(0x80 | (cp & 0x3F));
        } else {
            out += static_cast<char>(0xF0 | (cp >> 18));
            out += static_cast<char>(0x80 | ((cp >> 12) & 0x3F));
            out += static_cast<char>(0x80 | ((cp >> 6) & 0x3F));
            out += static_cast<char>(0x80 | (cp & 0x3F));
        }
    }
    unsigned hex4() {
        if (k_ + 4 > s_.size()) error("a \\u escape needs four hex digits");
        unsigned cp = 0;
        for (int i = 0; i < 4; ++i) {
            const char h = s_[k_++];
            cp <<= 4;
            if (h >= '0' && h <= '9')
                cp |= h - '0';
            else if (h >= 'a' && h <= 'f')
                cp |= h - 'a' + 10;
            else if (h >= 'A' && h <= 'F')
                cp |= h - 'A' + 10;
            else
                error("a \\u escape needs four hex digits");
        }
        return cp;
    }
    std::string string() {
        ++k_; // "
        std::string out;
        for (;;) {
            if (k_ >= s_.size()) error("unterminated string");
            const char c = s_[k_];
            if (c == '"') {
                ++k_;
                return out;
            }
            if (static_cast<unsigned char>(c) < 0x20) error("a control character inside a string");
            if (c != '\\') {
                out += c;
                ++k_;
                continue;
            }
            if (++k_ >= s_.size()) error("unterminated string");
            const char e = s_[k_++];
            switch (e) {
            case '"':
            case '\\':
            case '/':
                out += e;
                break;
            case 'b':
                out += '\b';
                break;
            case 'f':
                out += '\f';
                break;
            case 'n':
                out += '\n';
                break;
            case 'r':
                out += '\r';
                break;
            case 't':
                out += '\t';
                break;
            case 'u': {
                unsigned cp = hex4();
                if (cp >= 0xD800 && cp < 0xDC00) {
                    if (s_.compare(k_, 2, "\\u") != 0) error("a lone surrogate in a \\u escape");
                    k_ += 2;
                    const unsigned low = hex4();
                    if (low < 0xDC00 || low >= 0xE000) error("a lone surrogate in a \\u escape");
                    cp = 0x10000 + ((cp - 0xD800) << 10) + (low - 0xDC00);
                } else if (cp >= 0xDC00 && cp < 0xE000) {
                    error("a lone surrogate in a \\u escape");
                }
                utf8(out, cp);
                break;
            }
            default:
                error(std::string("unknown escape '\\") + e + "'");
            }
        }
    }
    std::string number() {
        const size_t start = k_;
        auto digits = [&] {
            const size_t d = k_;
            while (k_ < s_.size() && s_[k_] >= '0' && s_[k_] <= '9')
                ++k_;
            return k_ > d;
        };
        if (s_[k_] == '-') ++k_;
        if (k_ < s_.size() && s_[k_] == '0') {
            ++k_;
            if (k_ < s_.size() && s_[k_] >= '0' && s_[k_] <= '9') error("a number with a leading zero");
        } else if (!digits()) {
            error("a digit is expected");
        }
        if (k_ < s_.size() && s_[k_] == '.') {
            ++k_;
            if (!digits()) error("a digit is expected after '.'");
        }
        if (k_ < s_.size() && (s_[k_] == 'e' || s_[k_] == 'E')) {
            ++k_;
            if (k_ < s_.size() && (s_[k_] == '+' || s_[k_] == '-')) ++k_;
            if (!digits()) error("a digit is expected in the exponent");
        }
        return s_.substr(start, k_ - start);
    }
};

// The field of a message named by a JSON key: its proto name or its JSON (lowerCamelCase) name.
const pb::FieldDescriptor* json_field(const pb::Descriptor* d, const std::string& key) {
    if (const auto* f = d->FindFieldByName(key)) return f;
    for (int i = 0; i < d->field_count(); ++i)
        if (d->field(i)->json_name() == key) return d->field(i);
    return nullptr;
}

// Fills a message from a JSON object, field by field through reflection, so that every error has a
// position. A number too large for a double becomes ±inf, which check_ranges refuses naming the field.
class JsonFiller {
  public:
    JsonFiller(const std::string& text, const std::string& file) : text_(text), file_(file) {}
    void object(const JsonValue& v, pb::Message& msg, const std::string& path) {
        if (v.kind != JsonValue::Object) fail(v, path, "an object { ... } is expected");
        const auto* d = msg.GetDescriptor();
        const auto* refl = msg.GetReflection();
        std::set<const pb::FieldDescriptor*> given;
        for (const auto& [key, value] : v.members) {
            const auto* f = json_field(d, key);
            if (!f) fail(value, path, d->name() + " has no field '" + key + "'");
            const std::string p = path.empty() ? f->name() : path + "." + f->name();
            if (!given.insert(f).second)
                fail(value, p, "the field is given twice (as '" + key + "' and another name)");
            if (const auto* o = f->containing_oneof(); o && refl->HasOneof(msg, o))
                fail(value, p,
                     "'" + f->name() + "' and '" + refl->GetOneofFieldDescriptor(msg, o)->name() +
                         "' are both given; '" + o->name() + "' holds one of them");
            if (value.kind == JsonValue::Null) fail(value, p, "null is not a value; leave the field out");
            if (f->is_repeated()) {
                if (value.kind != JsonValue::Array) fail(value, p, "a list [ ... ] is expected");
                if (!f->message_type() && value.elements.size() > static_cast<size_t>(max_list_size))
                    fail(value, p,
                         "the list holds " + std::to_string(value.elements.size()) + " numbers; at most " +
                             std::to_string(max_list_size));
                for (size_t i = 0; i < value.elements.size(); ++i)
                    element(value.elements[i], msg, f, p + "[" + std::to_string(i) + "]");
            } else {
                element(value, msg, f, p);
            }
        }
    }

  private:
    const std::string& text_;
    const std::string& file_;

    [[noreturn]] void fail(const JsonValue& v, const std::string& path, const std::string& message) const {
        throw CaseError(position(file_, text_, v.offset) + (path.empty() ? "" : ": " + path) + ": " +
                        message);
    }
    // An integer token (or, for 64-bit fields, a string holding one, as protobuf's JSON writes them).
    long long integer(const JsonValue& v, const std::string& path, long long lo, long long hi) const {
        const bool quoted = v.kind == JsonValue::String;
        if (v.kind != JsonValue::Number && !quoted) fail(v, path, "an integer is expected");
        errno = 0;
        char* end = nullptr;
        const long long x = std::strtoll(v.text.c_str(), &end, 10);
        if (v.text.empty() || *end != '\0') {
            // 1e3 or 20.0: an integer written as a real number.
            const double r = std::strtod(v.text.c_str(), &end);
            if (v.text.empty() || *end != '\0' || r != std::floor(r) || !(std::abs(r) < 9.2e18))
                fail(v, path, "'" + v.text + "' is not an integer");
            if (r < static_cast<double>(lo) || r > static_cast<double>(hi))
                fail(v, path, v.text + " is out of the range of the field's type");
            return static_cast<long long>(r);
        }
        if (errno == ERANGE || x < lo || x > hi)
            fail(v, path, v.text + " is out of the range of the field's type");
        return x;
    }
    void element(const JsonValue& v, pb::Message& msg, const pb::FieldDescriptor* f,
                 const std::string& path) {
        const auto* refl = msg.GetReflection();
        const bool rep = f->is_repeated();
        using FD = pb::FieldDescriptor;
        switch (f->cpp_type()) {
        case FD::CPPTYPE_MESSAGE:
            object(v, rep ? *refl->AddMessage(&msg, f) : *refl->MutableMessage(&msg, f), path);
            return;
        case FD::CPPTYPE_DOUBLE:
        case FD::CPPTYPE_FLOAT: {
            if (v.kind != JsonValue::Number) fail(v, path, "a number is expected");
            const double x = std::strtod(v.text.c_str(), nullptr);
            if (f->cpp_type() == FD::CPPTYPE_FLOAT)
                rep ? refl->AddFloat(&msg, f, static_cast<float>(x))
                    : refl->SetFloat(&msg, f, static_cast<float>(x));
            else
                rep ? refl->AddDouble(&msg, f, x) : refl->SetDouble(&msg, f, x);
            return;
        }
        case FD::CPPTYPE_INT32: {
            const auto x = static_cast<int32_t>(integer(v, path, INT32_MIN, INT32_MAX));
            rep ? refl->AddInt32(&msg, f, x) : refl->SetInt32(&msg, f, x);
            return;
        }
        case FD::CPPTYPE_INT64: {
            const auto x = static_cast<int64_t>(integer(v, path, INT64_MIN, INT64_MAX));
            rep ? refl->AddInt64(&msg, f, x) : refl->SetInt64(&msg, f, x);
            return;
        }
        case FD::CPPTYPE_UINT32: {
            const auto x = static_cast<uint32_t>(integer(v, path, 0, UINT32_MAX));
            rep ? refl->AddUInt32(&msg, f, x) : refl->SetUInt32(&msg, f, x);
            return;
        }
        case FD::CPPTYPE_UINT64: {
            const auto x = static_cast<uint64_t>(integer(v, path, 0, INT64_MAX));
            rep ? refl->AddUInt64(&msg, f, x) : refl->SetUInt64(&msg, f, x);
            return;
        }
        case FD::CPPTYPE_BOOL:
            if (v.kind != JsonValue::Bool) fail(v, path, "true or false is expected");
            rep ? refl->AddBool(&msg, f, v.boolean) : refl->SetBool(&msg, f, v.boolean);
            return;
        case FD::CPPTYPE_STRING:
            if (v.kind != JsonValue::String) fail(v, path, "a string in quotes is expected");
            rep ? refl->AddString(&msg, f, v.text) : refl->SetString(&msg, f, v.text);
            return;
        case FD::CPPTYPE_ENUM: {
            const auto* e = f->enum_type();
            const pb::EnumValueDescriptor* ev =
                v.kind == JsonValue::String ? e->FindValueByName(v.text)
                : v.kind == JsonValue::Number
                    ? e->FindValueByNumber(static_cast<int>(integer(v, path, INT32_MIN, INT32_MAX)))
                    : nullptr;
            if (!ev) {
                std::string names;
                for (int i = 0; i < e->value_count(); ++i)
                    names += (i ? ", " : "") + e->value(i)->name();
                fail(v, path, "'" + v.text + "' is not one of " + names);
            }
            rep ? refl->AddEnum(&msg, f, ev) : refl->SetEnum(&msg, f, ev);
            return;
        }
        }
    }
};

class Collector : public pb::io::ErrorCollector {
  public:
    explicit Collector(std::string file, std::string text = "")
        : file_(std::move(file)), text_(std::move(text)) {}
    void AddError(int line, pb::io::ColumnNumber column, const std::string& message) override {
        if (!first_.empty()) return;
        std::ostringstream s;
        s << file_;
        if (line >= 0) s << ':' << line + 1 << ':' << column + 1;
        // The field being read, unless protobuf's message names one itself.
        const std::string field = message.find("ield") == std::string::npos ? field_before(line, column) : "";
        if (!field.empty()) s << ": field '" << field << "'";
        s << ": " << message;
        first_ = s.str();
    }
    // The name of the field whose value the parser was reading: the last "name:" before the column (a
    // scan back from the column: linear in the line, however long).
    std::string field_before(int line, int column) const {
        if (line < 0) return "";
        size_t start = 0;
        for (int k = 0; k < line && start != std::string::npos; ++k)
            start = text_.find('\n', start) == std::string::npos ? std::string::npos
                                                                 : text_.find('\n', start) + 1;
        if (start == std::string::npos) return "";
        const size_t end = std::min(
            {text_.find('\n', start), start + static_cast<size_t>(std::max(column, 0)), text_.size()});
        const size_t colon = text_.rfind(':', end == 0 ? 0 : end - 1);
        if (colon == std::string::npos || colon < start || end == start) return "";
        size_t k = colon;
        while (k > start && (text_[k - 1] == ' ' || text_[k - 1] == '\t'))
            --k;
        const size_t name_end = k;
        const auto word = [](char c) {
            return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_';
        };
        while (k > start && word(text_[k - 1]))
            --k;
        if (k == name_end || (text_[k] >= '0' && text_[k] <= '9')) return "";
        return text_.substr(k, name_end - k);
    }
    void AddWarning(int, pb::io::ColumnNumber, const std::string&) override {}
    const std::string& first() const { return first_; }

  private:
    std::string file_, text_;
    std::string first_;
};

// One step of a field path: name and optional [index].
struct PathStep {
    std::string name;
    int index = -1;
};

// A field path "name[index].name...", strictly: names of letters, digits and '_' (not starting with a
// digit), indices of at most 9 decimal digits, nothing else. Throws std::invalid_argument saying what is
// wrong.
std::vector<PathStep> split_path(const std::string& path) {
    std::vector<PathStep> steps;
    size_t k = 0;
    const auto is_alpha = [](char c) { return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_'; };
    const auto is_digit = [](char c) { return c >= '0' && c <= '9'; };
    for (;;) {
        PathStep step;
        if (k >= path.size() || !is_alpha(path[k]))
            throw std::invalid_argument(k >= path.size() ? "a field name is missing at the end"
                                                         : "a field name is expected at character " +
                                                               std::to_string(k + 1));
        while (k < path.size() && (is_alpha(path[k]) || is_digit(path[k])))
            step.name += path[k++];
        if (k < path.size() && path[k] == '[') {
            const size_t start = ++k;
            while (k < path.size() && is_digit(path[k]))
                ++k;
            if (k == start || k - start > 9)
                throw std::invalid_argument("an index of up to 9 digits is expected after '" + step.name +
                                            "['");
            if (k >= path.size() || path[k] != ']')
                throw std::invalid_argument("']' is expected after '" + path.substr(0, k) + "'");
            step.index = std::stoi(path.substr(start, k - start));
            ++k;
        }
        steps.push_back(step);
        if (k == path.size()) return steps;
        if (path[k] != '.')
            throw std::invalid_argument("unexpected '" + path.substr(k, 1) + "' at character " +
                                        std::to_string(k + 1));
        ++k;
    }
}

std::string join_path(const std::vector<PathStep>& steps) {
    std::string s;
    for (const auto& st : steps)
        s += (s.empty() ? "" : ".") + st.name + (st.index >= 0 ? "[" + std::to_string(st.index) + "]" : "");
    return s;
}

// Applies "key=value"; returns the key as a canonical field path.
std::string apply_override(pb::Message& root, const std::string& assignment) {
    const auto eq = assignment.find('=');
    if (eq == std::string::npos) throw CaseError("--set " + assignment + ": expected key=value");
    const std::string key = assignment.substr(0, eq), value = assignment.substr(eq + 1);
    std::vector<PathStep> steps;
    try {
        steps = split_path(key);
    } catch (const std::invalid_argument& e) {
        throw CaseError("--set " + key + ": malformed field path: " + e.what());
    }
    pb::Message* msg = &root;
    for (size_t i = 0; i < steps.size(); ++i) {
        const auto* field = msg->GetDescriptor()->FindFieldByName(steps[i].name);
        if (!field)
            throw CaseError("--set " + key + ": " + msg->GetDescriptor()->name() + " has no field '" +
                            steps[i].name + "'");
        const auto* refl = msg->GetReflection();
        const bool last = i + 1 == steps.size();
        if (field->is_repeated() && steps[i].index < 0)
            throw CaseError("--set " + key + ": '" + steps[i].name + "' is a list; give an index, e.g. " +
                            steps[i].name + "[0]");
        if (!field->is_repeated() && steps[i].index >= 0)
            throw CaseError("--set " + key + ": '" + steps[i].name + "' is not a list; it takes no index");
        if (field->is_repeated() && steps[i].index >= refl->FieldSize(*msg, field))
            throw CaseError("--set " + key + ": '" + steps[i].name + "' has only " +
                            std::to_string(refl->FieldSize(*msg, field)) + " entries");
        // Setting a field of another choice of a oneof would silently replace the case's choice (e.g.
        // materials[0].tait.* on a stiffened gas would make it Tait water).
        if (const auto* o = field->containing_oneof(); o && refl->HasOneof(*msg, o)) {
            const auto* chosen = refl->GetOneofFieldDescriptor(*msg, o);
            if (chosen != field)
                throw CaseError("--set " + key + ": the case gives '" + chosen->name() + "' here, not '" +
                                field->name() + "' ('" + o->name() + "' holds one of them)");
        }
        if (!last) {
            if (field->cpp_type() != pb::FieldDescriptor::CPPTYPE_MESSAGE)
                throw CaseError("--set " + key + ": '" + steps[i].name + "' is not a message");
            msg = field->is_repeated() ? refl->MutableRepeatedMessage(msg, field, steps[i].index)
                                       : refl->MutableMessage(msg, field);
            continue;
        }
        if (field->cpp_type() == pb::FieldDescriptor::CPPTYPE_MESSAGE)
            throw CaseError("--set " + key + ": only scalar fields can be set");
        if (field->is_repeated()) {
            // Element of a list: only lists of numbers (output times, pressure tables) are repeated scalars.
            if (field->cpp_type() != pb::FieldDescriptor::CPPTYPE_DOUBLE)
                throw CaseError("--set " + key + ": only lists of numbers can be set element-wise");
            char* end = nullptr;
            const double x = std::strtod(value.c_str(), &end);
            if (value.empty() || *end != '\0')
                throw CaseError("--set " + key + ": '" + value + "' is not a number");
            refl->SetRepeatedDouble(msg, field, steps[i].index, x);
        } else if (field->cpp_type() == pb::FieldDescriptor::CPPTYPE_STRING) {
            refl->SetString(msg, field, value);
        } else {
            pb::TextFormat::Parser parser;
            Collector quiet("--set " + key);
            parser.RecordErrorsTo(&quiet);
            if (!parser.ParseFieldValueFromString(value, field, msg))
                throw CaseError("--set " + key + ": '" + value + "' is not a valid " + field->type_name());
        }
    }
    return join_path(steps);
}

// ---- Ranges (proto/case.proto: the options ge, gt, le, lt of a number field). ----

struct Range {
    bool has_lo = false, has_hi = false, lo_open = false, hi_open = false;
    double lo = 0, hi = 0;
    bool admits(double x) const {
        return std::isfinite(x) && (!has_lo || (lo_open ? x > lo : x >= lo)) &&
               (!has_hi || (hi_open ? x < hi : x <= hi));
    }
    std::string text() const;
};

// The shortest decimal that reads back as x.
std::string number_text(double x) {
    char b[32];
    const auto r = std::to_chars(b, b + sizeof b, x);
    return std::string(b, r.ptr);
}

std::string Range::text() const {
    return (lo_open ? "(" : "[") + (has_lo ? number_text(lo) : "-inf") + ", " +
           (has_hi ? number_text(hi) : "inf") + (hi_open ? ")" : "]");
}

bool is_number(const pb::FieldDescriptor* f) {
    using FD = pb::FieldDescriptor;
    switch (f->cpp_type()) {
    case FD::CPPTYPE_DOUBLE:
    case FD::CPPTYPE_FLOAT:
    case FD::CPPTYPE_INT32:
    case FD::CPPTYPE_INT64:
    case FD::CPPTYPE_UINT32:
    case FD::CPPTYPE_UINT64:
        return true;
    default:
        return false;
    }
}

Range range_of(const pb::FieldDescriptor* f) {
    const auto& o = f->options();
    Range r;
    if (o.HasExtension(config::gt)) r.has_lo = r.lo_open = true, r.lo = o.GetExtension(config::gt);
    if (o.HasExtension(config::ge)) r.has_lo = true, r.lo = o.GetExtension(config::ge);
    if (o.HasExtension(config::lt)) r.has_hi = r.hi_open = true, r.hi = o.GetExtension(config::lt);
    if (o.HasExtension(config::le)) r.has_hi = true, r.hi = o.GetExtension(config::le);
    return r;
}

// The value of a number field as a double (exact for every int32; int64 beyond 2^53 rounds, which moves no
// bound of the schema).
double number_value(const pb::Message& m, const pb::FieldDescriptor* f, int index) {
    const auto* r = m.GetReflection();
    const bool rep = index >= 0;
    using FD = pb::FieldDescriptor;
    switch (f->cpp_type()) {
    case FD::CPPTYPE_DOUBLE:
        return rep ? r->GetRepeatedDouble(m, f, index) : r->GetDouble(m, f);
    case FD::CPPTYPE_FLOAT:
        return rep ? r->GetRepeatedFloat(m, f, index) : r->GetFloat(m, f);
    case FD::CPPTYPE_INT32:
        return rep ? r->GetRepeatedInt32(m, f, index) : r->GetInt32(m, f);
    case FD::CPPTYPE_INT64:
        return static_cast<double>(rep ? r->GetRepeatedInt64(m, f, index) : r->GetInt64(m, f));
    case FD::CPPTYPE_UINT32:
        return rep ? r->GetRepeatedUInt32(m, f, index) : r->GetUInt32(m, f);
    default:
        return static_cast<double>(rep ? r->GetRepeatedUInt64(m, f, index) : r->GetUInt64(m, f));
    }
}

double default_number(const pb::FieldDescriptor* f) {
    using FD = pb::FieldDescriptor;
    switch (f->cpp_type()) {
    case FD::CPPTYPE_DOUBLE:
        return f->default_value_double();
    case FD::CPPTYPE_FLOAT:
        return f->default_value_float();
    case FD::CPPTYPE_INT32:
        return f->default_value_int32();
    case FD::CPPTYPE_INT64:
        return static_cast<double>(f->default_value_int64());
    case FD::CPPTYPE_UINT32:
        return f->default_value_uint32();
    default:
        return static_cast<double>(f->default_value_uint64());
    }
}

void schema_walk(const pb::Descriptor* d, std::set<const pb::Descriptor*>& seen,
                 std::vector<std::string>& out) {
    if (!seen.insert(d).second) return;
    for (int i = 0; i < d->field_count(); ++i) {
        const auto* f = d->field(i);
        if (f->message_type()) {
            schema_walk(f->message_type(), seen, out);
            continue;
        }
        if (!is_number(f)) continue;
        const Range r = range_of(f);
        const std::string name = d->name() + "." + f->name();
        if (!r.has_lo || !r.has_hi)
            out.push_back(name + ": no lower or no upper bound ((ge) or (gt), (le) or (lt))");
        else if (!(r.lo < r.hi))
            out.push_back(name + ": the range " + r.text() + " is empty");
        else if (f->has_default_value() && !r.admits(default_number(f)))
            out.push_back(name + ": the default lies outside " + r.text());
    }
}

// "must lie in (0, 1] (got 1.5; the range of Numerics.cfl in proto/case.proto)", or "must be a finite
// number in ..." for NaN and ±inf.
std::string out_of_range(double x, const Range& r, const pb::FieldDescriptor* f) {
    return std::string(std::isfinite(x) ? "must lie in " : "must be a finite number in ") + r.text() +
           " (got " + number_text(x) + "; the range of " + f->containing_type()->name() + "." + f->name() +
           " in proto/case.proto)";
}

// Every set number of m (and of its set messages) within its range.
void check_message(const CaseFile& cf, const pb::Message& m, const std::string& path) {
    const auto* d = m.GetDescriptor();
    const auto* refl = m.GetReflection();
    for (int i = 0; i < d->field_count(); ++i) {
        const auto* f = d->field(i);
        const std::string p = path.empty() ? f->name() : path + "." + f->name();
        if (f->is_repeated()) {
            const int n = refl->FieldSize(m, f);
            if (f->message_type()) {
                for (int k = 0; k < n; ++k)
                    check_message(cf, refl->GetRepeatedMessage(m, f, k), p + "[" + std::to_string(k) + "]");
                continue;
            }
            if (!is_number(f)) continue;
            if (n > max_list_size)
                cf.fail(p, "the list holds " + std::to_string(n) + " numbers; at most " +
                               std::to_string(max_list_size));
            const Range r = range_of(f);
            for (int k = 0; k < n; ++k) {
                const double x = number_value(m, f, k);
                if (!r.admits(x)) cf.fail(p + "[" + std::to_string(k) + "]", out_of_range(x, r, f));
            }
            continue;
        }
        if (!refl->HasField(m, f)) continue; // defaults are checked against their ranges by schema_problems
        if (f->message_type()) {
            check_message(cf, refl->GetMessage(m, f), p);
            continue;
        }
        if (!is_number(f)) continue;
        const Range r = range_of(f);
        const double x = number_value(m, f, -1);
        if (!r.admits(x)) cf.fail(p, out_of_range(x, r, f));
    }
}

// The case file's text, read only from a regular file of at most max_case_bytes (a directory, a device such
// as /dev/zero, a FIFO would never give a case, or never end).
std::string read_case_file(const std::string& path) {
    struct stat st {};
    if (stat(path.c_str(), &st) != 0)
        throw CaseError(path + ": cannot open the case file: " + std::strerror(errno));
    if (S_ISDIR(st.st_mode)) throw CaseError(path + ": is a directory, not a case file");
    if (!S_ISREG(st.st_mode))
        throw CaseError(path + ": is not a regular file (a device, FIFO or socket); a case is a file");
    const auto too_large = [&] {
        return CaseError(path + ": the case file is larger than " + std::to_string(max_case_bytes >> 20) +
                         " MiB, the most a case file may be");
    };
    if (st.st_size > max_case_bytes) throw too_large();
    std::ifstream in(path, std::ios::binary);
    if (!in) throw CaseError(path + ": cannot open the case file: " + std::strerror(errno));
    std::string text(static_cast<size_t>(max_case_bytes) + 1, '\0');
    in.read(text.data(), static_cast<std::streamsize>(text.size()));
    if (in.bad()) throw CaseError(path + ": cannot read the case file: " + std::strerror(errno));
    if (in.gcount() > max_case_bytes) throw too_large(); // it grew since stat
    text.resize(static_cast<size_t>(in.gcount()));
    return text;
}

} // namespace

struct CaseFile::Locations {
    pb::TextFormat::ParseInfoTree tree;
    bool available = false;
    std::string json_text; // a JSON case: its text and document, for where()
    std::unique_ptr<JsonValue> json;
};

CaseFile::CaseFile() : case_(std::make_unique<config::Case>()), locations_(std::make_unique<Locations>()) {}
CaseFile::CaseFile(CaseFile&&) noexcept = default;
CaseFile& CaseFile::operator=(CaseFile&&) noexcept = default;
CaseFile::~CaseFile() = default;

CaseFile CaseFile::from_text(const std::string& text, const std::string& name) {
    CaseFile c;
    c.path_ = name;
    if (text.size() > static_cast<size_t>(max_case_bytes))
        throw CaseError(name + ": the case is larger than " + std::to_string(max_case_bytes >> 20) + " MiB");
    const auto first = text.find_first_not_of(" \t\r\n");
    if (first != std::string::npos && text[first] == '{') {
        c.locations_->json_text = text;
        c.locations_->json =
            std::make_unique<JsonValue>(JsonReader(c.locations_->json_text, name).document());
        JsonFiller(c.locations_->json_text, name).object(*c.locations_->json, *c.case_, "");
    } else {
        pb::TextFormat::Parser parser;
        Collector collector(name, text);
        parser.RecordErrorsTo(&collector);
        parser.WriteLocationsTo(&c.locations_->tree);
        parser.AllowPartialMessage(true); // missing required fields are reported below, with a location
        if (!parser.ParseFromString(text, c.case_.get())) {
            if (!collector.first().empty()) throw CaseError(collector.first());
            throw CaseError(name + ": cannot be parsed");
        }
        c.locations_->available = true;
    }
    std::vector<std::string> missing;
    c.case_->FindInitializationErrors(&missing);
    if (!missing.empty()) c.fail(missing.front(), "required field is missing");
    return c;
}

CaseFile CaseFile::load(const std::string& path, const std::vector<std::string>& overrides) {
    CaseFile c = from_text(read_case_file(path), path);
    for (const auto& o : overrides)
        c.overridden_.push_back(apply_override(*c.case_, o));
    return c;
}

std::string CaseFile::where(const std::string& field_path) const {
    std::string set_below; // an override inside the field, e.g. box.x_min for a box
    for (const auto& o : overridden_) {
        if (o == field_path) return "--set " + field_path;
        if (o.compare(0, field_path.size() + 1, field_path + ".") == 0)
            set_below = " (after --set " + o + ")";
    }
    std::string location = path_;
    try {
        const auto steps = split_path(field_path);
        if (locations_->json) {
            // The key of the deepest member of the path that the file gives.
            const JsonValue* v = locations_->json.get();
            long at = -1;
            const pb::Descriptor* d = case_->GetDescriptor();
            for (const auto& step : steps) {
                const pb::FieldDescriptor* f = d ? d->FindFieldByName(step.name) : nullptr;
                if (!f || v->kind != JsonValue::Object) break;
                const JsonValue* next = nullptr;
                for (const auto& [key, member] : v->members)
                    if (key == f->name() || key == f->json_name()) next = &member;
                if (!next) break;
                at = next->offset;
                v = next;
                if (step.index >= 0) {
                    if (v->kind != JsonValue::Array || step.index >= static_cast<int>(v->elements.size()))
                        break;
                    v = &v->elements[step.index];
                    at = v->offset;
                }
                d = f->message_type();
            }
            if (at >= 0) location = position(path_, locations_->json_text, at);
        } else if (locations_->available) {
            const pb::Message* msg = case_.get();
            const pb::TextFormat::ParseInfoTree* tree = &locations_->tree;
            int line = -1, col = -1;
            for (size_t i = 0; i < steps.size() && tree && msg; ++i) {
                const auto* field = msg->GetDescriptor()->FindFieldByName(steps[i].name);
                if (!field) break;
                const int index = field->is_repeated() ? std::max(steps[i].index, 0) : -1;
                const auto loc = tree->GetLocation(field, index);
                if (loc.line >= 0) line = loc.line, col = loc.column;
                if (field->cpp_type() != pb::FieldDescriptor::CPPTYPE_MESSAGE) break;
                tree = tree->GetTreeForNested(field, index);
                const auto* refl = msg->GetReflection();
                if (field->is_repeated()) {
                    if (index >= refl->FieldSize(*msg, field)) break;
                    msg = &refl->GetRepeatedMessage(*msg, field, index);
                } else {
                    msg = &refl->GetMessage(*msg, field);
                }
            }
            if (line >= 0) location += ":" + std::to_string(line + 1) + ":" + std::to_string(col + 1);
        }
    } catch (const std::exception&) {
    }
    return location + ": " + field_path + set_below;
}

void CaseFile::fail(const std::string& field_path, const std::string& message) const {
    throw CaseError(where(field_path) + ": " + message);
}

std::string CaseFile::text() const {
    std::string out;
    pb::TextFormat::PrintToString(*case_, &out);
    return out;
}

std::vector<std::string> schema_problems() {
    std::vector<std::string> out;
    std::set<const pb::Descriptor*> seen;
    schema_walk(config::Case::descriptor(), seen, out);
    return out;
}

void CaseFile::check_ranges() const {
    static const std::vector<std::string> problems = schema_problems();
    if (!problems.empty()) throw std::logic_error("proto/case.proto: " + problems.front());
    check_message(*this, *case_, "");
}

} // namespace undex
