// Reading a case file (protobuf text format or JSON of proto/case.proto) with command-line overrides,
// and reporting errors that name the file, line and field.
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
} // namespace undex
