// The fault log's schema (src/log/schema.hpp) pinned to its reference, docs/fault-log.md:
// every event name is the heading of its record's section (### `name`), every field name and
// `outcome` value is written in the reference as code (`name`, or a member of an example
// record), and the table below holds every constant of the header — so a constant renamed,
// added or removed without the reference (and this table) following fails here.
#include "log/schema.hpp"
#include "support/paths.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace keel::log {
namespace {

namespace fs = std::filesystem;
namespace ev = schema::event;
namespace fd = schema::field;

/// keel's source tree (KEEL_EXAMPLES is its examples/ directory).
const fs::path kSource = fs::path(KEEL_EXAMPLES).parent_path();

struct Constant {
  const char* name;      // as declared in schema.hpp
  const char* spelling;  // its value, as the log writes it
};

const Constant kEvents[] = {
    {"kInjected", ev::kInjected},
    {"kArmed", ev::kArmed},
    {"kDetected", ev::kDetected},
    {"kDiagnosed", ev::kDiagnosed},
    {"kAction", ev::kAction},
    {"kRecovered", ev::kRecovered},
    {"kState", ev::kState},
    {"kEmergency", ev::kEmergency},
    {"kEngine", ev::kEngine},
    {"kWarning", ev::kWarning},
    {"kEndRequested", ev::kEndRequested},
    {"kHost", ev::kHost},
    {"kNode", ev::kNode},
    {"kCounts", ev::kCounts},
};

const Constant kFields[] = {
    {"kEvent", fd::kEvent},
    {"kTime", fd::kTime},
    {"kFaultId", fd::kFaultId},
    {"kComponent", fd::kComponent},
    {"kApplication", fd::kApplication},
    {"kComposite", fd::kComposite},
    {"kKind", fd::kKind},
    {"kDetail", fd::kDetail},
    {"kDetector", fd::kDetector},
    {"kMeasurement", fd::kMeasurement},
    {"kDetected", fd::kDetected},
    {"kSeverity", fd::kSeverity},
    {"kRules", fd::kRules},
    {"kScope", fd::kScope},
    {"kHandling", fd::kHandling},
    {"kAction", fd::kAction},
    {"kOutcome", fd::kOutcome},
    {"kReplacement", fd::kReplacement},
    {"kAlternative", fd::kAlternative},
    {"kServing", fd::kServing},
    {"kComponents", fd::kComponents},
    {"kApplications", fd::kApplications},
    {"kFrom", fd::kFrom},
    {"kTo", fd::kTo},
    {"kLatencyUs", fd::kLatencyUs},
    {"kPhase", fd::kPhase},
    {"kBy", fd::kBy},
    {"kMessage", fd::kMessage},
    {"kReason", fd::kReason},
    {"kSummary", fd::kSummary},
    {"kOnFaultManagerThread", fd::kOnFaultManagerThread},
    {"kNotFinished", fd::kNotFinished},
    {"kHardware", fd::kHardware},
    {"kFieldsError", fd::kFieldsError},
    {"kProfile", fd::kProfile},
    {"kInstances", fd::kInstances},
    {"kSet", fd::kSet},
    {"kEpochNs", fd::kEpochNs},
    {"kExecutors", fd::kExecutors},
    {"kCpuDmaLatencyUs", fd::kCpuDmaLatencyUs},
    {"kProcess", fd::kProcess},
    {"kPid", fd::kPid},
    {"kNodeName", fd::kNodeName},
    {"kLastLines", fd::kLastLines},
    {"kAfterMs", fd::kAfterMs},
    {"kOutput", fd::kOutput},
    {"kParams", fd::kParams},
    {"kName", fd::kName},
    {"kClass", fd::kClass},
    {"kExecutor", fd::kExecutor},
    {"kExecutions", fd::kExecutions},
    {"kDeadlineMisses", fd::kDeadlineMisses},
    {"kPeriodMs", fd::kPeriodMs},
    {"kCycles", fd::kCycles},
    {"kLateCycles", fd::kLateCycles},
};

/// The values of `outcome` (schema::kOk, schema::kFailed).
const Constant kOutcomes[] = {{"kOk", schema::kOk}, {"kFailed", schema::kFailed}};

std::string readFile(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  EXPECT_TRUE(in) << "cannot read " << path;
  std::ostringstream out;
  out << in.rdbuf();
  return out.str();
}

/// What docs/fault-log.md writes as code.
struct Reference {
  std::set<std::string> headings;  // `name` of every "### `name`" heading: the records' sections
  std::set<std::string> code;      // every `code span`, and the name of a member `"name": ...` in one
  std::set<std::string> members;   // the members of the example records (```json blocks)
  std::set<std::string> examples;  // the `event` of each example record
};

Reference readReference() {
  std::istringstream doc(readFile(kSource / "docs" / "fault-log.md"));
  Reference ref;
  const std::regex heading(R"(^### `([^`]+)`\s*$)");
  const std::regex span(R"(`([^`\n]+)`)");
  const std::regex member(R"re(^"([^"]+)"\s*:)re");
  bool in_json = false, in_block = false;
  std::smatch m;
  for (std::string line; std::getline(doc, line);) {
    if (line.rfind("```", 0) == 0) {
      in_json = !in_block && line == "```json";
      in_block = !in_block;
      continue;
    }
    if (in_block) {
      if (in_json && !line.empty()) {
        const nlohmann::json record = nlohmann::json::parse(line);
        for (const auto& [key, value] : record.items()) ref.members.insert(key);
        ref.examples.insert(record.value(fd::kEvent, ""));
      }
      continue;
    }
    if (std::regex_match(line, m, heading)) ref.headings.insert(m[1]);
    for (std::sregex_iterator it(line.begin(), line.end(), span), end; it != end; ++it) {
      const std::string code = (*it)[1];
      ref.code.insert(code);
      if (std::regex_search(code, m, member)) ref.code.insert(m[1]);
    }
  }
  return ref;
}

/// The constants schema.hpp declares in `namespace <ns> { ... }` ("" for those outside
/// event and field), by name.
std::map<std::string, std::string> declaredIn(const std::string& ns) {
  const std::string header = readFile(kSource / "src" / "log" / "schema.hpp");
  const std::regex constant(R"re(inline constexpr char (k\w+)\[\] = "([^"]*)";)re");
  const std::regex opening(R"re(^namespace (\w+) \{)re"), closing(R"re(^\}  // namespace (\w+)$)re");
  std::map<std::string, std::string> out;
  std::istringstream in(header);
  std::string current;  // the namespace the line is in, below keel::log::schema
  std::smatch m;
  for (std::string line; std::getline(in, line);) {
    if (std::regex_search(line, m, opening)) current = m[1];
    else if (std::regex_search(line, m, closing)) current.clear();
    else if (current == ns && std::regex_search(line, m, constant)) out[m[1]] = m[2];
  }
  return out;
}

template <std::size_t N>
std::map<std::string, std::string> byName(const Constant (&table)[N]) {
  std::map<std::string, std::string> out;
  for (const Constant& c : table) out[c.name] = c.spelling;
  return out;
}

TEST(LogSchema, TheTablesHereHoldEveryConstantOfTheHeader) {
  EXPECT_EQ(byName(kEvents), declaredIn("event")) << "an event constant added, removed or renamed: update kEvents";
  EXPECT_EQ(byName(kFields), declaredIn("field")) << "a field constant added, removed or renamed: update kFields";
  EXPECT_EQ(byName(kOutcomes), declaredIn("")) << "an outcome constant added, removed or renamed: update kOutcomes";
}

TEST(LogSchema, EveryEventHasItsSectionInTheReference) {
  const Reference ref = readReference();
  ASSERT_FALSE(ref.headings.empty()) << "no ### `record` sections found in docs/fault-log.md";
  std::set<std::string> events;
  for (const Constant& e : kEvents) {
    events.insert(e.spelling);
    EXPECT_TRUE(ref.headings.count(e.spelling))
        << "schema::event::" << e.name << " is \"" << e.spelling << "\", which docs/fault-log.md has no ### `"
        << e.spelling << "` section for";
  }
  for (const std::string& h : ref.headings)
    EXPECT_TRUE(events.count(h)) << "docs/fault-log.md documents a record `" << h << "` that has no event constant";
}

TEST(LogSchema, EveryFieldIsDocumentedInTheReference) {
  const Reference ref = readReference();
  for (const Constant& f : kFields)
    EXPECT_TRUE(ref.code.count(f.spelling) || ref.members.count(f.spelling))
        << "schema::field::" << f.name << " is \"" << f.spelling << "\", which docs/fault-log.md never writes as `"
        << f.spelling << "`";
}

TEST(LogSchema, EveryOutcomeIsDocumentedInTheReference) {
  const Reference ref = readReference();
  for (const Constant& o : kOutcomes)
    EXPECT_TRUE(ref.code.count(o.spelling)) << "schema::" << o.name << " is \"" << o.spelling
                                            << "\", which docs/fault-log.md never writes as `" << o.spelling << "`";
}

TEST(LogSchema, TheExampleRecordsUseOnlyTheSchemasNames) {
  // The worked example's records are built from the same names: every member is a field, and
  // every event one of the events.
  const Reference ref = readReference();
  ASSERT_FALSE(ref.members.empty()) << "no ```json example records found in docs/fault-log.md";
  std::set<std::string> fields, events;
  for (const Constant& f : kFields) fields.insert(f.spelling);
  for (const Constant& e : kEvents) events.insert(e.spelling);
  for (const std::string& m : ref.members)
    EXPECT_TRUE(fields.count(m)) << "example member `" << m << "` has no field constant";
  for (const std::string& e : ref.examples)
    EXPECT_TRUE(events.count(e)) << "example event `" << e << "` has no event constant";
}

}  // namespace
}  // namespace keel::log
