// Reading a case file (protobuf text format or JSON of proto/case.proto) with command-line overrides,
// and reporting errors that name the file, line and field. Case files are regular files of at most
// max_case_bytes; JSON is read strictly (RFC 8259: no duplicate keys, trailing commas or comments), with
// line and column in every error, as text format is.
#pragma once
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace undex {
namespace config {
class Case;
}

// A bad case: the message already names the file, line and field.
struct CaseError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

// The largest case file read: 8 MiB holds a 500 000-point pressure table; reading it, in either format,
// takes well under 1 GiB of memory (a JSON value in memory is about 100 bytes, for 2 bytes of text at least).
constexpr long max_case_bytes = 8L << 20;
// The most numbers a list of the case (output times, pressure tables, foam curves) may hold.
constexpr int max_list_size = 1000000;

class CaseFile {
  public:
    // Parses `path` and applies overrides "key=value" (key: a field path such as numerics.cfl or
    // regions[1].rho). Throws CaseError.
    static CaseFile load(const std::string& path, const std::vector<std::string>& overrides = {});
    // Parses a case given as text (for tests and for cases stored in output files).
    static CaseFile from_text(const std::string& text, const std::string& name = "<case>");

    const config::Case& get() const { return *case_; }
    const std::string& path() const { return path_; }
    // "file:line:col: field" for a field path like "regions[1].rho" (or "--set field" if overridden).
    std::string where(const std::string& field_path) const;
    // Throws CaseError "where(field_path): message".
    [[noreturn]] void fail(const std::string& field_path, const std::string& message) const;
    // The case after overrides, in text format (stored with every output).
    std::string text() const;
    // Checks every number of the case against its range in proto/case.proto (finite, within the bounds
    // (ge), (gt), (le), (lt) of its field; lists at most max_list_size long); throws CaseError naming the
    // field and the range. The solvers' validation (validate_plan) calls it first.
    void check_ranges() const;

    CaseFile(CaseFile&&) noexcept;
    CaseFile& operator=(CaseFile&&) noexcept;
    ~CaseFile();

  private:
    CaseFile();
    struct Locations;
    std::string path_;
    std::unique_ptr<config::Case> case_;
    std::unique_ptr<Locations> locations_;
    std::vector<std::string> overridden_;
};
// The fields of proto/case.proto that break the rule of its header (a number field without both a lower and
// an upper bound, a default outside its range), as "Message.field: problem"; empty when the schema is sound.
// check_ranges throws std::logic_error when it is not, so that a new field cannot forget its range.
std::vector<std::string> schema_problems();

} // namespace undex
