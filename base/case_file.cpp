#include "base/case_file.hpp"

#include "proto/case.pb.h"

#include <google/protobuf/io/tokenizer.h>
#include <google/protobuf/text_format.h>
#include <google/protobuf/util/json_util.h>

#include <cstdlib>
#include <fstream>
#include <regex>
#include <sstream>

namespace undex {

namespace pb = google::protobuf;

struct CaseFile::Locations {
    pb::TextFormat::ParseInfoTree tree;
    bool available = false;
};

namespace {

class Collector : public pb::io::ErrorCollector {
  public:
    explicit Collector(std::string file, std::string text = "")
        : file_(std::move(file)), text_(std::move(text)) {}
    void AddError(int line, pb::io::ColumnNumber column, const std::string& message) override {
        if (!first_.empty()) return;
        std::ostringstream s;
        s << file_;
        if (line >= 0) s << ':' << line + 1 << ':' << column + 1;
        const std::string field = field_before(line, column);
        if (!field.empty()) s << ": field '" << field << "'";
        s << ": " << message;
        first_ = s.str();
    }
    // The name of the field whose value the parser was reading: the last "name:" before the column.
    std::string field_before(int line, int column) const {
        if (line < 0) return "";
        std::istringstream in(text_);
        std::string l;
        for (int k = 0; k <= line && std::getline(in, l); ++k) {
        }
        static const std::regex assignment(R"(([A-Za-z_][A-Za-z0-9_]*)\s*:\s*[^:]*$)");
        std::smatch m;
        const std::string before = l.substr(0, std::min<size_t>(column, l.size()));
        return std::regex_search(before, m, assignment) ? m[1].str() : "";
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

std::vector<PathStep> split_path(const std::string& path) {
    std::vector<PathStep> steps;
    std::stringstream ss(path);
    std::string part;
    while (std::getline(ss, part, '.')) {
        PathStep step;
        const auto bracket = part.find('[');
        if (bracket != std::string::npos) {
            step.name = part.substr(0, bracket);
            step.index = std::stoi(part.substr(bracket + 1));
        } else {
            step.name = part;
        }
        steps.push_back(step);
    }
    return steps;
}

void apply_override(pb::Message& root, const std::string& assignment) {
    const auto eq = assignment.find('=');
    if (eq == std::string::npos) throw CaseError("--set " + assignment + ": expected key=value");
    const std::string key = assignment.substr(0, eq), value = assignment.substr(eq + 1);
    std::vector<PathStep> steps;
    try {
        steps = split_path(key);
    } catch (const std::exception&) {
        throw CaseError("--set " + key + ": malformed field path");
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
        if (field->is_repeated() && steps[i].index >= refl->FieldSize(*msg, field))
            throw CaseError("--set " + key + ": '" + steps[i].name + "' has only " +
                            std::to_string(refl->FieldSize(*msg, field)) + " entries");
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
}

} // namespace

CaseFile::CaseFile() : case_(std::make_unique<config::Case>()), locations_(std::make_unique<Locations>()) {}
CaseFile::CaseFile(CaseFile&&) noexcept = default;
CaseFile& CaseFile::operator=(CaseFile&&) noexcept = default;
CaseFile::~CaseFile() = default;

CaseFile CaseFile::from_text(const std::string& text, const std::string& name) {
    CaseFile c;
    c.path_ = name;
    const auto first = text.find_first_not_of(" \t\r\n");
    if (first != std::string::npos && text[first] == '{') {
        pb::util::JsonParseOptions options;
        const auto status = pb::util::JsonStringToMessage(text, c.case_.get(), options);
        if (!status.ok()) throw CaseError(name + ": " + std::string(status.message()));
        std::vector<std::string> missing;
        c.case_->FindInitializationErrors(&missing);
        if (!missing.empty()) throw CaseError(name + ": missing required field '" + missing.front() + "'");
        return c;
    }
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
    std::vector<std::string> missing;
    c.case_->FindInitializationErrors(&missing);
    if (!missing.empty()) c.fail(missing.front(), "required field is missing");
    return c;
}

CaseFile CaseFile::load(const std::string& path, const std::vector<std::string>& overrides) {
    std::ifstream in(path);
    if (!in) throw CaseError(path + ": cannot open the case file");
    std::stringstream buffer;
    buffer << in.rdbuf();
    CaseFile c = from_text(buffer.str(), path);
    for (const auto& o : overrides) {
        apply_override(*c.case_, o);
        c.overridden_.push_back(o.substr(0, o.find('=')));
    }
    return c;
}

std::string CaseFile::where(const std::string& field_path) const {
    for (const auto& o : overridden_)
        if (o == field_path) return "--set " + field_path;
    std::string location = path_;
    if (locations_->available) {
        try {
            const pb::Message* msg = case_.get();
            const pb::TextFormat::ParseInfoTree* tree = &locations_->tree;
            int line = -1, col = -1;
            const auto steps = split_path(field_path);
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
        } catch (const std::exception&) {
        }
    }
    return location + ": " + field_path;
}

void CaseFile::fail(const std::string& field_path, const std::string& message) const {
    throw CaseError(where(field_path) + ": " + message);
}

std::string CaseFile::text() const {
    std::string out;
    pb::TextFormat::PrintToString(*case_, &out);
    return out;
}

} // namespace undex
