// The key table (config/key_table.h): one declaration reads a key, reports it at file:line:col, and
// describes it for the reference and the JSON Schema.
#include <gtest/gtest.h>

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "hadal/config/key_doc.h"
#include "hadal/config/key_table.h"

namespace hadal::config {
namespace {

enum class Shape { kBall, kRod };

struct Probe {
  Shape shape = Shape::kBall;
  double radius = 0.5;              // [m]
  double length = 2.0;              // [m], rods only
  double tilt = 15.0 * kDegToRad;   // [rad]
  int rays = 4;
  std::optional<double> gain;
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();
};

const KeyTable<Probe>& probe_keys() {
  return declare_keys<Probe>([](KeyTable<Probe>& t) {
    t.describe("probe", "a test probe");
    t.choice("shape", &Probe::shape, {{"ball", Shape::kBall}, {"rod", Shape::kRod, "a thin cylinder"}})
        .selects("probe shape").doc("its shape");
    t.number("radius", &Probe::radius).unit("m").range(Range::positive()).doc("its radius");
    t.number("length", &Probe::length).only_for({"rod"}).required_for({"rod"}).unit("m").range(Range::positive())
        .doc("its length");
    t.number("tilt_deg", &Probe::tilt).degrees().range(Range::closed(0.0, 90.0)).doc("its tilt");
    t.number("rays", &Probe::rays).range(Range::closed(1.0, 64.0)).doc("rays it casts");
    t.number("gain", &Probe::gain).unit("dB").doc("an optional gain");
    t.vector("offset", &Probe::offset).unit("m").doc("where it sits");
    t.check([](const KeyReads& reads, Probe& probe, NoContext&) {
      if (!reads.ok("radius") || !reads.ok("length") || probe.shape != Shape::kRod || probe.length > probe.radius) {
        return true;
      }
      reads.error_at_key("length", "a rod is longer than its radius");
      return false;
    });
  });
}

struct Read {
  bool ok = false;
  Probe probe;
  std::vector<std::string> errors;
};

Read read(const std::string& yaml) {
  DiagnosticSink sink;
  sink.add_file("p.yaml");
  const auto source = std::make_shared<const Source>(Source{"p.yaml", &sink, nullptr, nullptr, {}});
  Read out;
  out.ok = probe_keys().read(Value::root(YAML::Load(yaml), source), &out.probe);
  for (const Diagnostic& d : sink.sorted()) out.errors.push_back(d.format());
  return out;
}

TEST(KeyTableTest, ReadsEachKeyIntoItsFieldInItsUnit) {
  const Read r = read("{shape: rod, radius: 0.25, length: 3, tilt_deg: 30, rays: 8, gain: -6, offset: [1, -2, 3]}");
  ASSERT_TRUE(r.ok) << (r.errors.empty() ? "" : r.errors[0]);
  EXPECT_EQ(r.probe.shape, Shape::kRod);
  EXPECT_EQ(r.probe.radius, 0.25);
  EXPECT_EQ(r.probe.length, 3.0);
  EXPECT_EQ(r.probe.tilt, 30.0 * kDegToRad);  // the same operation as the code's constants: bit for bit
  EXPECT_EQ(r.probe.rays, 8);
  ASSERT_TRUE(r.probe.gain.has_value());
  EXPECT_EQ(*r.probe.gain, -6.0);
  EXPECT_EQ(r.probe.offset, Eigen::Vector3d(1.0, -2.0, 3.0));
}

TEST(KeyTableTest, KeysNotGivenKeepTheirDefaultsBitForBit) {
  const Read r = read("{radius: 1}");
  ASSERT_TRUE(r.ok);
  EXPECT_EQ(r.probe.tilt, 15.0 * kDegToRad);  // not read back through degrees
  EXPECT_FALSE(r.probe.gain.has_value());
  EXPECT_EQ(r.probe.rays, 4);
}

TEST(KeyTableTest, EveryProblemIsReportedAtItsNode) {
  const Read r = read("{shape: ball, radius: -1, length: 3, tilt_deg: 95, rays: 2.5, gian: 3}");
  EXPECT_FALSE(r.ok);
  EXPECT_EQ(r.errors, (std::vector<std::string>{
                          "p.yaml:1:23: error: radius: must be > 0 (got -1)",
                          "p.yaml:1:27: error: length: key 'length' is not used by probe shape 'ball'",
                          "p.yaml:1:48: error: tilt_deg: must be in [0, 90] (got 95)",
                          "p.yaml:1:58: error: rays: must be a whole number (got 2.5)",
                          "p.yaml:1:63: error: gian: unknown key 'gian'; did you mean 'gain'?"}));
}

TEST(KeyTableTest, TheSelectorDecidesWhatIsRequiredAndChecksRunLast) {
  EXPECT_EQ(read("{shape: rod}").errors,
            (std::vector<std::string>{"p.yaml:1:1: error: missing required key 'length' (needed by probe shape 'rod')"}));
  EXPECT_EQ(read("{shape: rod, radius: 2, length: 1}").errors,
            (std::vector<std::string>{"p.yaml:1:25: error: length: a rod is longer than its radius"}));
  // An invalid selector is one error: the keys that depend on it are not judged by a guess.
  EXPECT_EQ(read("{shape: cone, length: 1}").errors,
            (std::vector<std::string>{"p.yaml:1:9: error: shape: must be one of 'ball', 'rod' (got 'cone')"}));
}

TEST(KeyTableTest, TheDescriptionShowsDefaultsInTheYamlsUnitAndTheRules) {
  const TableDoc& doc = probe_keys().doc();
  ASSERT_EQ(doc.keys.size(), 7u);
  EXPECT_EQ(doc.selector(), doc.find("shape"));
  EXPECT_EQ(doc.find("shape")->default_choice, "ball");
  EXPECT_EQ(doc.find("tilt_deg")->unit, "deg");
  EXPECT_EQ(doc.find("tilt_deg")->default_text, "15");
  EXPECT_EQ(doc.find("length")->default_text, "required for `rod`");
  EXPECT_EQ(doc.find("gain")->default_text, "none");
  EXPECT_EQ(doc.find("offset")->default_text, "[0, 0, 0]");
  EXPECT_EQ(doc.find("rays")->default_text, "4");
  const std::string table = reference_table(doc);
  EXPECT_NE(table.find("| `length` | number | m | required for `rod` | > 0 | `rod` only: its length |"), std::string::npos)
      << table;
  EXPECT_NE(table.find("| `rays` | integer | – | 4 | whole number in [1, 64] | rays it casts |"), std::string::npos)
      << table;
  EXPECT_NE(table.find("`ball`, `rod` (a thin cylinder)"), std::string::npos) << table;
}

TEST(KeyTableTest, TheReferenceKeepsItsProseAndNamesWhatItCannotPlace) {
  const TableDoc& doc = probe_keys().doc();
  const ReferenceUpdate update = update_reference(
      "# Probes\n\nProse before.\n\n<!-- keys: probe -->\nstale\n<!-- end keys -->\n\nProse after.\n"
      "<!-- keys: nothing -->\n<!-- end keys -->\n",
      {&doc});
  EXPECT_EQ(update.text.find("stale"), std::string::npos);
  EXPECT_EQ(update.text.rfind("# Probes\n\nProse before.\n\n<!-- keys: probe -->\n| Key |", 0), 0u) << update.text;
  EXPECT_NE(update.text.find("<!-- end keys -->\n\nProse after.\n"), std::string::npos);
  EXPECT_TRUE(update.missing.empty());
  EXPECT_EQ(update.unknown, (std::vector<std::string>{"nothing"}));
  EXPECT_EQ(update_reference("no markers\n", {&doc}).missing, (std::vector<std::string>{"probe"}));
  // Made anew from its own output, nothing changes.
  EXPECT_EQ(update_reference(update.text, {&doc}).text, update.text);
}

}  // namespace
}  // namespace hadal::config
