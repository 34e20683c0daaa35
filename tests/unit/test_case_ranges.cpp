// The ranges of proto/case.proto and the validator that reads them (CaseFile::check_ranges).
#include "base/case_file.hpp"
#include "proto/case.pb.h"

#include <gtest/gtest.h>

#include <google/protobuf/descriptor.h>

#include <cmath>
#include <filesystem>
#include <functional>
#include <limits>

namespace {

namespace pb = google::protobuf;
using undex::CaseError;
using undex::CaseFile;

// Every number field has a lower and an upper bound, and every explicit default lies within them: a new
// field without a range fails here (and makes every check throw std::logic_error).
TEST(CaseRanges, EveryNumberFieldHasARange) {
    const auto problems = undex::schema_problems();
    for (const auto& p : problems)
        ADD_FAILURE() << "proto/case.proto: " << p;
    EXPECT_TRUE(problems.empty());
}

// Calls f(path, message, field, index) for every number set in m (index −1: a singular field).
void for_each_number(
    pb::Message& m, const std::string& path,
    const std::function<void(const std::string&, pb::Message&, const pb::FieldDescriptor*, int)>& f) {
    const auto* d = m.GetDescriptor();
    const auto* r = m.GetReflection();
    for (int i = 0; i < d->field_count(); ++i) {
        const auto* fd = d->field(i);
        const std::string p = path.empty() ? fd->name() : path + "." + fd->name();
        if (fd->is_repeated()) {
            for (int k = 0; k < r->FieldSize(m, fd); ++k) {
                const std::string pk = p + "[" + std::to_string(k) + "]";
                if (fd->message_type())
                    for_each_number(*r->MutableRepeatedMessage(&m, fd, k), pk, f);
                else if (fd->cpp_type() == pb::FieldDescriptor::CPPTYPE_DOUBLE)
                    f(pk, m, fd, k);
            }
        } else if (r->HasField(m, fd)) {
            if (fd->message_type())
                for_each_number(*r->MutableMessage(&m, fd), p, f);
            else if (fd->cpp_type() == pb::FieldDescriptor::CPPTYPE_DOUBLE ||
                     fd->cpp_type() == pb::FieldDescriptor::CPPTYPE_INT32 ||
                     fd->cpp_type() == pb::FieldDescriptor::CPPTYPE_INT64)
                f(p, m, fd, -1);
        }
    }
}

// Sets a number field (double or integer; an integer gets the value rounded toward zero, if it fits).
bool set_number(pb::Message& m, const pb::FieldDescriptor* f, int index, double x) {
    const auto* r = m.GetReflection();
    switch (f->cpp_type()) {
    case pb::FieldDescriptor::CPPTYPE_DOUBLE:
        index < 0 ? r->SetDouble(&m, f, x) : r->SetRepeatedDouble(&m, f, index, x);
        return true;
    case pb::FieldDescriptor::CPPTYPE_INT32:
        if (!(std::abs(x) < 2e9)) return false;
        r->SetInt32(&m, f, static_cast<int32_t>(x));
        return true;
    case pb::FieldDescriptor::CPPTYPE_INT64:
        if (!(std::abs(x) < 9e18)) return false;
        r->SetInt64(&m, f, static_cast<int64_t>(x));
        return true;
    default:
        return false;
    }
}

template <class Extension> double option(const pb::FieldDescriptor* f, const Extension& e, bool& has) {
    has = f->options().HasExtension(e);
    return has ? f->options().GetExtension(e) : 0;
}

// For every number of every shipped case: NaN, ±inf, just beyond each bound and an exclusive bound itself
// are refused, naming the field; the case as shipped passes.
TEST(CaseRanges, EveryNumberOfTheShippedCasesIsChecked) {
    int refused = 0;
    for (const auto& entry : std::filesystem::directory_iterator(UNDEX_CASES)) {
        if (entry.path().extension() != ".case") continue;
        const std::string path = entry.path().string();
        EXPECT_NO_THROW(CaseFile::load(path).check_ranges()) << path;
        CaseFile probe = CaseFile::load(path);
        auto& root = const_cast<undex::config::Case&>(probe.get());
        for_each_number(
            root, "", [&](const std::string& field, pb::Message& m, const pb::FieldDescriptor* f, int index) {
                const auto* r = m.GetReflection();
                const double saved =
                    f->cpp_type() == pb::FieldDescriptor::CPPTYPE_DOUBLE
                        ? (index < 0 ? r->GetDouble(m, f) : r->GetRepeatedDouble(m, f, index))
                    : f->cpp_type() == pb::FieldDescriptor::CPPTYPE_INT32
                        ? r->GetInt32(m, f)
                        : static_cast<double>(r->GetInt64(m, f));
                bool has_ge, has_gt, has_le, has_lt;
                const double ge = option(f, undex::config::ge, has_ge),
                             gt = option(f, undex::config::gt, has_gt);
                const double le = option(f, undex::config::le, has_le),
                             lt = option(f, undex::config::lt, has_lt);
                const double inf = std::numeric_limits<double>::infinity();
                std::vector<double> bad = {std::nan(""), inf, -inf};
                // Just beyond a bound: by 1 for an integer, by a relative 1e-9 for a double.
                const bool integer = f->cpp_type() != pb::FieldDescriptor::CPPTYPE_DOUBLE;
                const auto step = [&](double b) { return integer ? 1.0 : std::max(1.0, std::abs(b)) * 1e-9; };
                if (has_ge) bad.push_back(ge - step(ge));
                if (has_gt) bad.push_back(gt);
                if (has_le) bad.push_back(le + step(le));
                if (has_lt) bad.push_back(lt);
                for (double x : bad) {
                    if (!set_number(m, f, index, x)) continue;
                    try {
                        probe.check_ranges();
                        ADD_FAILURE() << path << ": " << field << " = " << x << " was accepted";
                    } catch (const CaseError& e) {
                        EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
                        ++refused;
                    }
                }
                set_number(m, f, index, saved);
            });
        EXPECT_NO_THROW(probe.check_ranges()) << path << " after restoring every number";
    }
    EXPECT_GT(refused, 500); // about 100 numbers in the shipped cases, four or five bad values each
}

} // namespace
