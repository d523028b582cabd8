// ConfigNode's typed getters and checks, ranges, colours, SplitList,
// ParseFiniteDouble and DidYouMean. A probe entity type hands the test the
// ConfigNode the loader made for its element, so the getters run on a real
// parsed element with its file and line. Suites are named core_test_* so
// `ctest -R core_test` selects them.
#include "core/config.h"

#include <functional>
#include <string>
#include <vector>

#include "core/entity_type.h"
#include "tests/test_util.h"

namespace colony {
namespace {

using testing::Experiment;
using testing::LoadXml;

// What the current test does with the probe's node.
const std::function<void(const ConfigNode&)>* g_inspect = nullptr;
// Thrown by the probe after a clean inspection, to stop the load there.
struct Inspected {};

class ProbeType : public EntityType {
 public:
  void Build(const ConfigNode& node, EntityDesc& desc) const override {
    if (!g_inspect) return;
    (*g_inspect)(node);
    node.context().diagnostics.ThrowIfAny();
    throw Inspected{};
  }
  bool has_body() const override { return false; }
};

std::vector<AttributeDoc> ProbeAttributes() {
  std::vector<AttributeDoc> docs;
  for (const char* name :
       {"text", "number", "count", "flag", "triple", "mode", "tint", "blank", "txet"}) {
    docs.push_back({name, "anything", "", "probe attribute"});
  }
  return docs;
}

COLONY_REGISTER_ENTITY(ProbeType, "config_probe", "core_test: hands its element to the test",
                       ProbeAttributes(), {});

// Loads an experiment whose arena holds `element` (a <config_probe id="p">
// on line 2), runs `inspect` on its ConfigNode and returns every problem the
// calls recorded, one per line ("" if none).
std::string Inspect(const std::string& element,
                    const std::function<void(const ConfigNode&)>& inspect) {
  g_inspect = &inspect;
  std::string problems;
  try {
    LoadXml(Experiment("\n" + element));
    ADD_FAILURE() << "the probe was never built";
  } catch (const Inspected&) {
  } catch (const ConfigError& e) {
    problems = e.what();
  }
  g_inspect = nullptr;
  return problems;
}

bool Contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

TEST(core_test_config, NodeKnowsItsNameLineFileAndLabel) {
  std::string name, label, file;
  int line = 0;
  bool has_text = true, has_id = false;
  std::vector<std::string> attributes;
  EXPECT_EQ(Inspect("<config_probe id=\"p\" number=\"1\"/>",
                    [&](const ConfigNode& n) {
                      name = n.name();
                      label = n.Label();
                      file = n.file();
                      line = n.line();
                      has_text = n.Has("text");
                      has_id = n.Has("id");
                      attributes = n.AttributeNames();
                    }),
            "");
  EXPECT_EQ(name, "config_probe");
  EXPECT_EQ(label, "config_probe id=\"p\"");
  EXPECT_EQ(file, "<string>");
  EXPECT_EQ(line, 2);
  EXPECT_FALSE(has_text);
  EXPECT_TRUE(has_id);
  EXPECT_EQ(attributes, (std::vector<std::string>{"id", "number"}));
}

TEST(core_test_config, GetStringAndRequireString) {
  std::string text, fallback, required;
  EXPECT_EQ(Inspect("<config_probe id=\"p\" text=\"hello world\"/>",
                    [&](const ConfigNode& n) {
                      text = n.GetString("text", "none");
                      fallback = n.GetString("mode", "none");
                      required = n.RequireString("text");
                    }),
            "");
  EXPECT_EQ(text, "hello world");
  EXPECT_EQ(fallback, "none");
  EXPECT_EQ(required, "hello world");

  const std::string problems =
      Inspect("<config_probe id=\"p\" blank=\"\"/>", [&](const ConfigNode& n) {
        n.RequireString("text");
        n.RequireString("blank");
      });
  EXPECT_TRUE(Contains(
      problems,
      "<string>:2: <config_probe id=\"p\"> attribute 'text': required attribute is missing"))
      << problems;
  EXPECT_TRUE(Contains(problems, "attribute 'blank': must not be empty")) << problems;
}

TEST(core_test_config, GetDoubleReadsFiniteNumbersAndFallsBack) {
  double spaced = 0, exponent = 0, missing = 0;
  EXPECT_EQ(Inspect("<config_probe id=\"p\" number=\" 2.5 \" count=\"-1e-3\"/>",
                    [&](const ConfigNode& n) {
                      spaced = n.GetDouble("number", -1);
                      exponent = n.GetDouble("count", -1);
                      missing = n.GetDouble("text", 42);
                    }),
            "");
  EXPECT_EQ(spaced, 2.5);
  EXPECT_EQ(exponent, -1e-3);
  EXPECT_EQ(missing, 42);
}

TEST(core_test_config, GetDoubleRejectsWhatIsNotAFiniteNumber) {
  for (const std::string bad : {"abc", "", "1.5m", "1,5", "inf", "-inf", "nan", "1e999"}) {
    double v = 0;
    const std::string problems =
        Inspect("<config_probe id=\"p\" number=\"" + bad + "\"/>",
                [&](const ConfigNode& n) { v = n.GetDouble("number", 7); });
    EXPECT_EQ(v, 7) << "a bad value gives the fallback: " << bad;
    EXPECT_TRUE(Contains(problems, "<string>:2: <config_probe id=\"p\"> attribute 'number': '" +
                                       bad + "' is not a finite number; accepted: a finite number"))
        << problems;
  }
}

TEST(core_test_config, GetDoubleChecksRanges) {
  struct Case {
    std::string value;
    Range range;
    bool ok;
    std::string accepted;
  } cases[] = {
      {"0", Range::Positive(), false, "accepted: a number > 0"},
      {"1e-9", Range::Positive(), true, ""},
      {"-0.1", Range::NonNegative(), false, "accepted: a number >= 0"},
      {"0", Range::NonNegative(), true, ""},
      {"3", Range::Between(1, 2), false, "accepted: a number in [1, 2]"},
      {"1", Range::Between(1, 2), true, ""},
      {"2", Range::Between(1, 2), true, ""},
      {"0", Range{0, 10, true}, false, "accepted: a number in (0, 10]"},
      {"10", Range{0, 10, true}, true, ""},
      {"11", Range{0, 10, true}, false, "accepted: a number in (0, 10]"},
  };
  for (const auto& c : cases) {
    double v = 0;
    const std::string problems =
        Inspect("<config_probe id=\"p\" number=\"" + c.value + "\"/>",
                [&](const ConfigNode& n) { v = n.GetDouble("number", -5, c.range); });
    if (c.ok) {
      EXPECT_EQ(problems, "") << c.value;
      EXPECT_EQ(v, std::stod(c.value));
    } else {
      EXPECT_EQ(v, -5) << c.value;
      EXPECT_TRUE(Contains(problems, "'" + c.value + "' is out of range; " + c.accepted))
          << problems;
    }
  }
}

TEST(core_test_config, RequireDoubleNamesWhatIsAccepted) {
  const std::string problems = Inspect("<config_probe id=\"p\"/>", [&](const ConfigNode& n) {
    n.RequireDouble("number", Range::Positive());
  });
  EXPECT_TRUE(Contains(problems,
                       "attribute 'number': required attribute is missing; accepted: a number > 0"))
      << problems;
}

TEST(core_test_config, GetIntReadsWholeNumbers) {
  int64_t plain = 0, spaced = 0, negative = 0, missing = 0;
  EXPECT_EQ(Inspect("<config_probe id=\"p\" count=\"42\" number=\" 7 \" text=\"-3\"/>",
                    [&](const ConfigNode& n) {
                      plain = n.GetInt("count", 0);
                      spaced = n.GetInt("number", 0);
                      negative = n.GetInt("text", 0, -10, 10);
                      missing = n.GetInt("mode", 9);
                    }),
            "");
  EXPECT_EQ(plain, 42);
  EXPECT_EQ(spaced, 7);
  EXPECT_EQ(negative, -3);
  EXPECT_EQ(missing, 9);
}

TEST(core_test_config, GetIntRejectsFractionsGarbageAndOutOfRange) {
  struct Case {
    std::string value, problem;
  } cases[] = {
      {"1.5", "'1.5' is not a whole number; accepted: a whole number in [0, 256]"},
      {"ten", "'ten' is not a whole number; accepted: a whole number in [0, 256]"},
      {"", "'' is not a whole number"},
      {"99999999999999999999", "'99999999999999999999' is not a whole number"},
      {"-1", "'-1' is out of range; accepted: a whole number in [0, 256]"},
      {"257", "'257' is out of range; accepted: a whole number in [0, 256]"},
  };
  for (const auto& c : cases) {
    int64_t v = 0;
    const std::string problems =
        Inspect("<config_probe id=\"p\" count=\"" + c.value + "\"/>",
                [&](const ConfigNode& n) { v = n.GetInt("count", 5, 0, 256); });
    EXPECT_EQ(v, 5) << c.value;
    EXPECT_TRUE(Contains(problems, "attribute 'count': " + c.problem)) << problems;
  }
  // Unbounded above: described as such, not with INT64_MAX.
  const std::string problems = Inspect("<config_probe id=\"p\" count=\"-2\"/>",
                                       [&](const ConfigNode& n) { n.GetInt("count", 0); });
  EXPECT_TRUE(Contains(problems, "accepted: a whole number >= 0")) << problems;
  const std::string missing = Inspect("<config_probe id=\"p\"/>",
                                      [&](const ConfigNode& n) { n.RequireInt("count", 1, 9); });
  EXPECT_TRUE(
      Contains(missing, "required attribute is missing; accepted: a whole number in [1, 9]"))
      << missing;
}

TEST(core_test_config, GetBoolAcceptsOnlyTrueAndFalse) {
  bool t = false, f = true, fallback = false;
  EXPECT_EQ(Inspect("<config_probe id=\"p\" flag=\"true\" text=\"false\"/>",
                    [&](const ConfigNode& n) {
                      t = n.GetBool("flag", false);
                      f = n.GetBool("text", true);
                      fallback = n.GetBool("mode", true);
                    }),
            "");
  EXPECT_TRUE(t);
  EXPECT_FALSE(f);
  EXPECT_TRUE(fallback);
  bool v = false;
  const std::string problems = Inspect("<config_probe id=\"p\" flag=\"yes\"/>",
                                       [&](const ConfigNode& n) { v = n.GetBool("flag", true); });
  EXPECT_TRUE(v);
  EXPECT_TRUE(Contains(problems, "attribute 'flag': 'yes' is not a boolean; accepted: true, false"))
      << problems;
}

TEST(core_test_config, GetTripleReadsThreeNumbers) {
  std::array<double, 3> t{}, fallback{};
  EXPECT_EQ(Inspect("<config_probe id=\"p\" triple=\"1, -2.5 ,3e1\"/>",
                    [&](const ConfigNode& n) {
                      t = n.GetTriple("triple", {0, 0, 0});
                      fallback = n.GetTriple("text", {4, 5, 6});
                    }),
            "");
  EXPECT_EQ(t, (std::array<double, 3>{1, -2.5, 30}));
  EXPECT_EQ(fallback, (std::array<double, 3>{4, 5, 6}));

  for (const std::string bad : {"1,2", "1,2,3,4", "1,x,3", "1,,3", "1,2,inf", ""}) {
    std::array<double, 3> v{};
    const std::string problems =
        Inspect("<config_probe id=\"p\" triple=\"" + bad + "\"/>", [&](const ConfigNode& n) {
          v = n.GetTriple("triple", {7, 8, 9});
        });
    EXPECT_EQ(v, (std::array<double, 3>{7, 8, 9})) << bad;
    EXPECT_TRUE(Contains(problems, "attribute 'triple': '" + bad +
                                       "' is not three finite numbers; accepted: \"x,y,z\""))
        << problems;
  }
  const std::string range =
      Inspect("<config_probe id=\"p\" triple=\"1,0,1\"/>",
              [&](const ConfigNode& n) { n.GetTriple("triple", {}, Range::Positive()); });
  EXPECT_TRUE(Contains(range, "'1,0,1' is out of range; accepted: a number > 0")) << range;
  const std::string missing =
      Inspect("<config_probe id=\"p\"/>", [&](const ConfigNode& n) { n.RequireTriple("triple"); });
  EXPECT_TRUE(
      Contains(missing, "attribute 'triple': required attribute is missing; accepted: \"x,y,z\""))
      << missing;
}

TEST(core_test_config, GetChoiceSuggestsTheClosestChoice) {
  const std::vector<std::string> choices = {"uniform", "gaussian", "constant"};
  std::string chosen, fallback;
  EXPECT_EQ(Inspect("<config_probe id=\"p\" mode=\"gaussian\"/>",
                    [&](const ConfigNode& n) {
                      chosen = n.GetChoice("mode", choices, "uniform");
                      fallback = n.GetChoice("text", choices, "constant");
                    }),
            "");
  EXPECT_EQ(chosen, "gaussian");
  EXPECT_EQ(fallback, "constant");
  std::string v;
  const std::string problems =
      Inspect("<config_probe id=\"p\" mode=\"gausian\"/>",
              [&](const ConfigNode& n) { v = n.GetChoice("mode", choices, "uniform"); });
  EXPECT_EQ(v, "uniform");
  EXPECT_TRUE(Contains(
      problems,
      "attribute 'mode': 'gausian' is not accepted; accepted: uniform, gaussian, constant"))
      << problems;
  EXPECT_TRUE(Contains(problems, "did you mean 'gaussian'?")) << problems;
}

TEST(core_test_config, ParseColorNamesGreysAndComponents) {
  EXPECT_EQ(ParseColor("red"), (Color{255, 0, 0, 255}));
  EXPECT_EQ(ParseColor("white"), Color::White());
  EXPECT_EQ(ParseColor("off"), Color::Black());
  EXPECT_EQ(ParseColor("gray50"), (Color{127, 127, 127, 255}));
  EXPECT_EQ(ParseColor("grey80"), ParseColor("gray80"));
  EXPECT_EQ(ParseColor("10,20,30"), (Color{10, 20, 30, 255}));
  EXPECT_EQ(ParseColor(" 10 , 20 , 30 , 40 "), (Color{10, 20, 30, 40}));
  for (const char* bad : {"pinkish", "Red", "gray5", "gray100", "gray05", "256,0,0", "-1,0,0",
                          "1,2", "1,2,3,4,5", "1.5,2,3", "a,b,c", ""}) {
    EXPECT_FALSE(ParseColor(bad).has_value()) << bad;
  }
}

TEST(core_test_config, GetColorReportsWhatIsAccepted) {
  Color named, fallback;
  EXPECT_EQ(Inspect("<config_probe id=\"p\" tint=\"blue\"/>",
                    [&](const ConfigNode& n) {
                      named = n.GetColor("tint", Color::Black());
                      fallback = n.GetColor("text", Color{1, 2, 3, 4});
                    }),
            "");
  EXPECT_EQ(named, (Color{0, 0, 255, 255}));
  EXPECT_EQ(fallback, (Color{1, 2, 3, 4}));
  Color bad;
  const std::string problems =
      Inspect("<config_probe id=\"p\" tint=\"300,0,0\"/>",
              [&](const ConfigNode& n) { bad = n.GetColor("tint", Color::White()); });
  EXPECT_EQ(bad, Color::White());
  EXPECT_TRUE(Contains(
      problems,
      std::string("attribute 'tint': '300,0,0' is not a colour; accepted: ") + kColorAccepted))
      << problems;
}

TEST(core_test_config, ChildrenAndChild) {
  size_t all = 0, named = 0;
  bool has_b = false, has_z = true, invalid_has = true;
  int b_line = 0;
  std::string invalid_read;
  EXPECT_EQ(Inspect("<config_probe id=\"p\">\n<a/>\n<b/>\n<a/></config_probe>",
                    [&](const ConfigNode& n) {
                      all = n.Children().size();
                      named = n.Children("a").size();
                      has_b = n.Child("b").valid();
                      b_line = n.Child("b").line();
                      const ConfigNode z = n.Child("z");
                      has_z = z.valid();
                      // An absent child reads as empty, never crashes.
                      invalid_has = z.Has("x");
                      invalid_read = z.GetString("x", "fallback");
                      EXPECT_TRUE(z.Children().empty());
                      EXPECT_FALSE(z.Child("y").valid());
                    }),
            "");
  EXPECT_EQ(all, 3u);
  EXPECT_EQ(named, 2u);
  EXPECT_TRUE(has_b);
  EXPECT_EQ(b_line, 4);
  EXPECT_FALSE(has_z);
  EXPECT_FALSE(invalid_has);
  EXPECT_EQ(invalid_read, "fallback");
}

TEST(core_test_config, CheckAttributesChildrenAndAtMostOne) {
  const std::string problems =
      Inspect("<config_probe id=\"p\" txet=\"x\">\n<a/>\n<b/>\n<a/></config_probe>",
              [&](const ConfigNode& n) {
                n.CheckAttributes({"id", "text"});
                n.CheckChildren({"a"});
                n.CheckAtMostOne("a");
              });
  EXPECT_TRUE(Contains(problems,
                       "<string>:2: <config_probe id=\"p\"> attribute 'txet': unknown attribute "
                       "(did you mean 'text'?); accepted: id, text"))
      << problems;
  EXPECT_TRUE(
      Contains(problems, "<string>:4: <b>: unknown element inside <config_probe>; accepted: a"))
      << problems << "(no 'did you mean' between unrelated one-letter names)";
  EXPECT_TRUE(
      Contains(problems,
               "<string>:5: <a>: <a> given more than once inside <config_probe> (first at line 3)"))
      << problems;
  const std::string none =
      Inspect("<config_probe id=\"p\"><a/></config_probe>", [&](const ConfigNode& n) {
        n.Child("a").CheckChildren({});
        n.CheckAttributes({"id"});
      });
  EXPECT_EQ(none, "");
  const std::string takes_none = Inspect("<config_probe id=\"p\"><a/></config_probe>",
                                         [&](const ConfigNode& n) { n.CheckChildren({}); });
  EXPECT_TRUE(Contains(takes_none,
                       "<a>: unknown element inside <config_probe>; it takes no child elements"))
      << takes_none;
}

TEST(core_test_config, EveryProblemOfOneNodeIsReportedTogether) {
  const std::string problems =
      Inspect("<config_probe id=\"p\" number=\"x\" count=\"1.5\" flag=\"maybe\"/>",
              [&](const ConfigNode& n) {
                n.GetDouble("number", 0);
                n.GetInt("count", 0);
                n.GetBool("flag", false);
              });
  EXPECT_TRUE(Contains(problems, "attribute 'number'")) << problems;
  EXPECT_TRUE(Contains(problems, "attribute 'count'")) << problems;
  EXPECT_TRUE(Contains(problems, "attribute 'flag'")) << problems;
  EXPECT_EQ(std::count(problems.begin(), problems.end(), '\n'), 2) << problems;
}

TEST(core_test_config, ErrorAndElementErrorFormat) {
  const std::string problems = Inspect("<config_probe id=\"p\"/>", [&](const ConfigNode& n) {
    n.Error("number", "12", "too big; accepted: a number <= 10");
    n.ElementError("something is off");
  });
  EXPECT_TRUE(Contains(
      problems,
      "<string>:2: <config_probe id=\"p\"> attribute 'number': too big; accepted: a number <= 10"))
      << problems;
  EXPECT_TRUE(Contains(problems, "<string>:2: <config_probe id=\"p\">: something is off"))
      << problems;
}

TEST(core_test_config, ToParamsCarriesEveryAttribute) {
  Params params;
  EXPECT_EQ(Inspect("<config_probe id=\"p\" number=\"0.5\" text=\"hi\"/>",
                    [&](const ConfigNode& n) { params = n.ToParams(); }),
            "");
  EXPECT_EQ(params.GetDouble("number", 0), 0.5);
  EXPECT_EQ(params.GetString("text", ""), "hi");
  EXPECT_EQ(params.GetString("id", ""), "p");
  EXPECT_TRUE(params.Unread().empty());
}

TEST(core_test_config, DiagnosticToString) {
  EXPECT_EQ((Diagnostic{"f.xml", 3, "box id=\"b\"", "size", "1", "bad; accepted: x"}).ToString(),
            "f.xml:3: <box id=\"b\"> attribute 'size': bad; accepted: x");
  EXPECT_EQ((Diagnostic{"f.xml", 0, "", "", "", "empty"}).ToString(), "f.xml: empty");
  EXPECT_EQ((Diagnostic{"", 0, "", "", "", "no file"}).ToString(), "no file");
  const ConfigError error(
      std::vector<Diagnostic>{{"a.xml", 1, "x", "", "", "one"}, {"a.xml", 2, "y", "", "", "two"}});
  EXPECT_EQ(std::string(error.what()), "a.xml:1: <x>: one\na.xml:2: <y>: two");
  EXPECT_EQ(error.diagnostics().size(), 2u);
}

TEST(core_test_config, RangeDescribe) {
  EXPECT_EQ(Range{}.Describe(), "a finite number");
  EXPECT_EQ(Range::Positive().Describe(), "a number > 0");
  EXPECT_EQ(Range::NonNegative().Describe(), "a number >= 0");
  EXPECT_EQ(Range::Between(-1, 2.5).Describe(), "a number in [-1, 2.5]");
  EXPECT_EQ((Range{0, 1, true}).Describe(), "a number in (0, 1]");
  EXPECT_EQ((Range{-std::numeric_limits<double>::max(), 3}).Describe(), "a number <= 3");
}

TEST(core_test_config, SplitListTrimsAndKeepsEmptyParts) {
  EXPECT_EQ(SplitList("a,b,c"), (std::vector<std::string>{"a", "b", "c"}));
  EXPECT_EQ(SplitList("  a , b  ,c "), (std::vector<std::string>{"a", "b", "c"}));
  EXPECT_EQ(SplitList("a,,b"), (std::vector<std::string>{"a", "", "b"}));
  EXPECT_EQ(SplitList("a,"), (std::vector<std::string>{"a", ""}));
  EXPECT_EQ(SplitList(""), (std::vector<std::string>{""}));
  EXPECT_EQ(SplitList("single"), (std::vector<std::string>{"single"}));
  EXPECT_EQ(SplitList("/a:/b c:", ':'), (std::vector<std::string>{"/a", "/b c", ""}));
}

TEST(core_test_config, ParseFiniteDouble) {
  double v = 0;
  EXPECT_TRUE(ParseFiniteDouble("1.25", v));
  EXPECT_EQ(v, 1.25);
  EXPECT_TRUE(ParseFiniteDouble(" -3e2 ", v));
  EXPECT_EQ(v, -300);
  v = 9;
  for (const char* bad : {"", " ", "abc", "1.5x", "1 2", "inf", "nan", "1e999", "0x"}) {
    EXPECT_FALSE(ParseFiniteDouble(bad, v)) << bad;
    EXPECT_EQ(v, 9) << "a failed parse leaves the output alone: " << bad;
  }
}

TEST(core_test_config, DidYouMeanPicksTheClosestTypoOnly) {
  const std::vector<std::string> attributes = {"length", "ticks_per_second", "random_seed"};
  EXPECT_EQ(DidYouMean("lenght", attributes), "length");
  EXPECT_EQ(DidYouMean("ticks_per_secnd", attributes), "ticks_per_second");
  EXPECT_EQ(DidYouMean("randomseed", attributes), "random_seed");
  EXPECT_EQ(DidYouMean("velocity", attributes), "") << "nothing close: no suggestion";
  EXPECT_EQ(DidYouMean("x", {}), "");
  EXPECT_EQ(DidYouMean("framwork", {"framework", "arena", "controllers"}), "framework");
  EXPECT_EQ(DidYouMean("marxbott", {"marxbot", "box", "cylinder"}), "marxbot");
  EXPECT_EQ(DidYouMean("bx", {"marxbot", "box", "cylinder"}), "box");
  // The closest wins over an earlier, farther one.
  EXPECT_EQ(DidYouMean("ticks_per_secnd", {"ticks_per_seconds", "ticks_per_second"}),
            "ticks_per_second");
  // Short names: a close one is suggested, a complete replacement is not.
  EXPECT_EQ(DidYouMean("b", {"a"}), "");
  EXPECT_EQ(DidYouMean("ab", {"cd"}), "");
  EXPECT_EQ(DidYouMean("ac", {"ab"}), "ab");
  // Swapped neighbours are one slip.
  EXPECT_EQ(DidYouMean("pm", {"mp"}), "mp");
  EXPECT_EQ(DidYouMean("lenght", {"length", "lengths"}), "length");
}

}  // namespace
}  // namespace colony

namespace colony {
namespace {

TEST(core_test_params, GetNumbersReadsAListStrictly) {
  Params p;
  p.Set("tilts", "25, 50,75");
  p.Set("bad", "25,5x");
  p.Set("short", "1,2,3");
  p.Set("high", "10,95");
  EXPECT_EQ(p.GetNumbers("tilts", ""), (std::vector<double>{25, 50, 75}));
  EXPECT_EQ(p.GetNumbers("absent", "-2,2", 2), (std::vector<double>{-2, 2}));
  auto message = [&](const char* key, size_t count, double max) {
    try {
      p.GetNumbers(key, "", count, -1e300, max);
    } catch (const ParamError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(message("bad", 0, 1e300).find("'5x' is not a finite number"), std::string::npos);
  EXPECT_NE(message("short", 4, 1e300).find("'1,2,3' has 3 numbers; accepted: 4 numbers"),
            std::string::npos);
  EXPECT_NE(message("high", 0, 90).find("95 is out of range"), std::string::npos);
}

// Every robot of a controller reads the same Params: the number is parsed
// once, yet each reader's range is still checked and a bad value still named.
TEST(core_test_params, GetDoubleChecksEveryReadersRange) {
  Params p;
  p.Set("speed", "0.5");
  p.Set("word", "fast");
  EXPECT_EQ(p.GetDouble("speed", 1, 0, 10), 0.5);
  EXPECT_EQ(p.GetDouble("speed", 1, 0, 10), 0.5);
  auto message = [&](const char* key, double min, double max) {
    try {
      p.GetDouble(key, 1, min, max);
    } catch (const ParamError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message("speed", 1, 2).find("0.5 is out of range"), std::string::npos);
  EXPECT_NE(message("word", 0, 10).find("'fast' is not a finite number"), std::string::npos);
  EXPECT_NE(message("word", 0, 10).find("'fast' is not a finite number"), std::string::npos);
  p.Set("speed", "3");  // set again: read afresh
  EXPECT_EQ(p.GetDouble("speed", 1, 0, 10), 3.0);
}

}  // namespace
}  // namespace colony
