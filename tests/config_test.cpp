// HM-style configuration (common/core/config.h): cfg syntax, ordering of -c files and --Key=value,
// short flags, booleans, enumerations, errors naming the origin and the key, and --help.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "common/core/config.h"
#include "common/core/error.h"
#include "common/media/media_version.h"
#include "encoder/encoder_params.h"
#include "tests/test_support.h"

namespace tdvo {
namespace {

using test::TempDir;

enum class Speed { kSlow, kMedium, kFast };

// A parameter struct with one field of every kind, bound to a table.
struct Params {
  std::string input = "in.obj";
  std::string output;
  int bits = 12;
  int count = 1;
  double rate = 25.0;
  bool verbose = false;
  bool trace = false;
  Speed speed = Speed::kMedium;

  OptionTable table{"tool", "tool -c FILE [--Key=value ...]"};

  Params() {
    table.section("Input");
    table.add("Input", input, "input file");
    table.add("Count", count, 1, 1000, "frames");
    table.add("Rate", rate, 0.5, 120.0, "frames per second");
    table.section("Coding");
    table.add("Bits", bits, 8, 20, "grid bits");
    table.addEnum("Speed", speed,
                  {{"slow", Speed::kSlow}, {"medium", Speed::kMedium}, {"fast", Speed::kFast}},
                  "speed preset");
    table.add("Verbose", verbose, "talk more");
    table.section("Output");
    table.add("Output", output, "output file", "-o");
    table.add("Trace", trace, "print a trace", "--trace");
  }

  // Runs parseCommandLine on {"tool", args...}.
  bool parse(std::vector<std::string> args) {
    std::vector<const char*> argv{"tool"};
    for (const std::string& a : args)
      argv.push_back(a.c_str());
    return table.parseCommandLine(static_cast<int>(argv.size()), argv.data());
  }

  // The Error message of parse(args); fails the test when there is none.
  std::string parseError(std::vector<std::string> args) {
    try {
      parse(std::move(args));
    } catch (const Error& e) {
      return e.what();
    }
    ADD_FAILURE() << "no error";
    return "";
  }

  std::string textError(const std::string& text, const std::string& origin = "a.cfg") {
    try {
      table.parseText(text, origin);
    } catch (const Error& e) {
      return e.what();
    }
    ADD_FAILURE() << "no error for:\n" << text;
    return "";
  }
};

// --help's default line of a key: "default: VALUE", or for a key derived while unset
// "default: not set (how; else VALUE)".
void expectDefaultShown(const std::string& line, const std::string& value, const std::string& key) {
  const std::string shown = line.substr(line.find_first_not_of(' '));
  const std::string fallback = "; else " + value + ")";
  EXPECT_TRUE(shown == "default: " + value ||
              (shown.rfind("default: not set (", 0) == 0 && shown.size() > fallback.size() &&
               shown.compare(shown.size() - fallback.size(), fallback.size(), fallback) == 0))
      << key << ": " << shown;
}

TEST(Config, CfgSyntax) {
  Params p;
  p.table.parseText(
      "# comment line\n"
      "\n"
      "Bits : 10   # trailing comment\n"
      "  Count\t:\t7\r\n"
      "Rate:29.97\n"
      "Input : my folder/frame %04d.obj  \n"
      "Output : C:/out.3dvo # a colon in the value\n"
      "Verbose : yes\n"
      "Speed : fast\n"
      "   # indented comment\n",
      "a.cfg");
  EXPECT_EQ(p.bits, 10);
  EXPECT_EQ(p.count, 7);
  EXPECT_EQ(p.rate, 29.97);
  EXPECT_EQ(p.input, "my folder/frame %04d.obj");
  EXPECT_EQ(p.output, "C:/out.3dvo");
  EXPECT_TRUE(p.verbose);
  EXPECT_EQ(p.speed, Speed::kFast);
  EXPECT_FALSE(p.trace);
  EXPECT_TRUE(p.table.wasSet("Bits"));
  EXPECT_FALSE(p.table.wasSet("Trace"));
  EXPECT_FALSE(p.table.wasSet("NoSuchKey"));
}

TEST(Config, LaterFilesAndOptionsWin) {
  TempDir dir("cfg");
  const std::string a = dir.file("a.cfg"), b = dir.file("b.cfg");
  test::writeText(a, "Bits : 9\nCount : 3\nInput : a.obj\n");
  test::writeText(b, "Bits : 11\nInput : b.obj\n");
  {
    Params p;
    ASSERT_TRUE(p.parse({"-c", a, "-c", b}));
    EXPECT_EQ(p.bits, 11);
    EXPECT_EQ(p.count, 3);
    EXPECT_EQ(p.input, "b.obj");
  }
  {
    Params p;
    ASSERT_TRUE(p.parse({"-c", b, "-c", a}));
    EXPECT_EQ(p.bits, 9);
    EXPECT_EQ(p.input, "a.obj");
  }
  {
    // Options and files apply in the order given.
    Params p;
    ASSERT_TRUE(p.parse({"-c", a, "--Bits=15", "-c", b, "--Count=8"}));
    EXPECT_EQ(p.bits, 11);
    EXPECT_EQ(p.count, 8);
  }
  {
    Params p;
    ASSERT_TRUE(p.parse({"--Bits=15", "-c", a, "-c", b, "--Bits=16", "--Input=x y.obj"}));
    EXPECT_EQ(p.bits, 16);
    EXPECT_EQ(p.input, "x y.obj");
  }
}

TEST(Config, ShortFlags) {
  Params p;
  ASSERT_TRUE(p.parse({"-o", "out.3dvo", "--trace"}));
  EXPECT_EQ(p.output, "out.3dvo");
  EXPECT_TRUE(p.trace);
  EXPECT_TRUE(p.table.wasSet("Output"));
  // The long form of the same key still works, and the last one wins.
  ASSERT_TRUE(p.parse({"--Output=long.3dvo", "-o", "short.3dvo", "--Trace=false"}));
  EXPECT_EQ(p.output, "short.3dvo");
  EXPECT_FALSE(p.trace);
}

// A long alias takes its value after '=' too (3dvo-dec --verify=FILE, as --verify FILE).
TEST(Config, LongAliasTakesItsValueAfterAnEqualsSign) {
  std::string log;
  OptionTable t("app", "usage");
  t.add("VerifyMd5", log, "the encoder's output", "--verify");
  const char* argv[] = {"app", "--verify=enc.log"};
  ASSERT_TRUE(t.parseCommandLine(2, argv));
  EXPECT_EQ(log, "enc.log");
  const char* spaced[] = {"app", "--verify", "other.log"};
  ASSERT_TRUE(t.parseCommandLine(3, spaced));
  EXPECT_EQ(log, "other.log");
}

TEST(Config, ShortFlagNeedsAValue) {
  Params p;
  EXPECT_EQ(p.parseError({"-o"}), "-o needs a value");
}

TEST(Config, BoolForms) {
  const std::vector<std::pair<std::string, bool>> forms = {
      {"true", true}, {"false", false}, {"1", true}, {"0", false}, {"yes", true}, {"no", false}};
  for (const auto& [text, value] : forms) {
    Params p;
    p.verbose = !value;
    p.table.set("Verbose", text, "test");
    EXPECT_EQ(p.verbose, value) << text;
    Params q;
    q.verbose = !value;
    ASSERT_TRUE(q.parse({"--Verbose=" + text}));
    EXPECT_EQ(q.verbose, value) << text;
  }
  Params p;
  ASSERT_TRUE(p.parse({"--Verbose"}));  // a bare boolean option means true
  EXPECT_TRUE(p.verbose);
  EXPECT_EQ(p.textError("Verbose : maybe\n"),
            "a.cfg:1: Verbose: 'maybe' is not a boolean (true/false, 1/0, yes/no)");
  EXPECT_EQ(p.textError("Verbose : TRUE\n"),
            "a.cfg:1: Verbose: 'TRUE' is not a boolean (true/false, 1/0, yes/no)");
}

TEST(Config, Enumeration) {
  Params p;
  ASSERT_TRUE(p.parse({"--Speed=slow"}));
  EXPECT_EQ(p.speed, Speed::kSlow);
  p.table.parseText("Speed : fast\n", "a.cfg");
  EXPECT_EQ(p.speed, Speed::kFast);
  EXPECT_EQ(p.parseError({"--Speed=ludicrous"}),
            "option --Speed=ludicrous: Speed: must be one of: slow | medium | fast");
  EXPECT_EQ(p.speed, Speed::kFast);  // a rejected value leaves the field alone
}

TEST(Config, Numbers) {
  Params p;
  ASSERT_TRUE(p.parse({"--Bits=8", "--Count=1000", "--Rate=0.5"}));
  EXPECT_EQ(p.bits, 8);
  EXPECT_EQ(p.count, 1000);
  EXPECT_EQ(p.rate, 0.5);
  ASSERT_TRUE(p.parse({"--Bits=20", "--Rate=120", "--Rate=1e1"}));
  EXPECT_EQ(p.bits, 20);
  EXPECT_EQ(p.rate, 10.0);
}

TEST(Config, UnknownKeyInFileNamesFileLineAndKey) {
  TempDir dir("cfgunknown");
  const std::string path = dir.file("bad.cfg");
  test::writeText(path, "Bits : 10\n# fine\nBitz : 11\n");
  Params p;
  EXPECT_EQ(p.parseError({"-c", path}), path + ":3: unknown key 'Bitz' (did you mean Bits?)");
}

TEST(Config, UnknownKeySuggestsTheNearestKey) {
  Params p;
  // Case, a swapped pair, a missing or an extra letter: the nearest key is named.
  EXPECT_EQ(p.textError("verbose : true\n"),
            "a.cfg:1: unknown key 'verbose' (did you mean Verbose?)");
  EXPECT_EQ(p.textError("Sped : fast\n"), "a.cfg:1: unknown key 'Sped' (did you mean Speed?)");
  EXPECT_EQ(p.textError("Outpt : x\n"), "a.cfg:1: unknown key 'Outpt' (did you mean Output?)");
  EXPECT_EQ(p.textError("Tracex : 1\n"), "a.cfg:1: unknown key 'Tracex' (did you mean Trace?)");
  // Nothing near: no guess.
  EXPECT_EQ(p.textError("Colour : red\n"), "a.cfg:1: unknown key 'Colour' (see --help)");
  EXPECT_EQ(p.textError("Q : 1\n"), "a.cfg:1: unknown key 'Q' (see --help)");
}

TEST(Config, Utf8ByteOrderMarkIsAccepted) {
  Params p;
  p.table.parseText(
      "\xEF\xBB\xBF"
      "Bits : 12\nRate : 30\n",
      "bom.cfg");
  EXPECT_EQ(p.bits, 12);
  EXPECT_EQ(p.rate, 30.0);
  // Only at the start of the text: elsewhere it is part of a key.
  Params q;
  EXPECT_EQ(q.textError("Bits : 12\n\xEF\xBB\xBF"
                        "Rate : 30\n")
                .rfind("a.cfg:2: unknown key", 0),
            0u);
}

// An error quotes input; its control characters are shown as \xNN, so the message is one whole
// line: a NUL in a cfg value cut the printed line short ("GridBits: '10"), an ESC reached the
// terminal.
TEST(Config, ErrorsShowControlCharactersAsHex) {
  Params p;
  EXPECT_EQ(p.textError(std::string("Bits : 1\0junk\n", 14)),
            "a.cfg:1: Bits: '1\\x00junk' is not an integer");
  EXPECT_EQ(p.textError("Bits : \x1b[31m\n"), "a.cfg:1: Bits: '\\x1b[31m' is not an integer");
  EXPECT_EQ(std::string(Error("x.obj:3: '\x7f\t' ä").what()), "x.obj:3: '\\x7f\\x09' ä");
}

// Bytes that are not well-formed UTF-8 (a Latin-1 name, a binary token, an overlong form, a
// surrogate, a cut sequence) and the C1 controls (CSI, U+009B) are shown as \xNN too; well-formed
// text of every length (2, 3 and 4 bytes) is kept.
TEST(Config, ErrorsShowBytesThatAreNotUtf8AsHex) {
  const auto shown = [](const std::string& s) { return std::string(Error(s).what()); };
  EXPECT_EQ(shown("caf\xe9.obj"), "caf\\xe9.obj");               // Latin-1
  EXPECT_EQ(shown("\xc0\xaf"), "\\xc0\\xaf");                    // overlong '/'
  EXPECT_EQ(shown("\xed\xa0\x80"), "\\xed\\xa0\\x80");           // a surrogate
  EXPECT_EQ(shown("\xf4\x90\x80\x80"), "\\xf4\\x90\\x80\\x80");  // above U+10FFFF
  EXPECT_EQ(shown("a\xe2\x82"), "a\\xe2\\x82");                  // cut at the end
  EXPECT_EQ(shown("\xe2\x82z"), "\\xe2\\x82z");                  // cut by ASCII
  EXPECT_EQ(shown("\xc2\x9b"
                  "31m"),
            "\\xc2\\x9b31m");  // C1 CSI
  EXPECT_EQ(shown("\xc2\xa0\xe2\x82\xac\xf0\x9f\x99\x82"),
            "\xc2\xa0\xe2\x82\xac\xf0\x9f\x99\x82");  // NBSP, euro sign, emoji kept
}

TEST(Config, VersionPrintsTheLibraries) {
  Params p;
  p.table.addVersionLines({"stream syntax version 7"});
  p.table.addVersionLines(mediaLibraryVersions());
  testing::internal::CaptureStdout();
  const bool go = p.parse({"--version"});
  const std::string out = testing::internal::GetCapturedStdout();
  EXPECT_FALSE(go);
  EXPECT_EQ(out.rfind("tool (3DVO ", 0), 0u) << out;
  for (const char* line : {"stream syntax version 7", "zlib ", "libpng ", "FFmpeg libavcodec ",
                           "FFmpeg libavformat ", "FFmpeg libavutil ", "FFmpeg libswscale "})
    EXPECT_NE(out.find(line), std::string::npos) << line << " missing in:\n" << out;
}

// The core layer's --version names only the core's libraries: a program that links the core
// alone (geometry) does not claim libpng or FFmpeg.
TEST(Config, CoreVersionNamesOnlyTheCoreLibraries) {
  Params p;
  testing::internal::CaptureStdout();
  p.parse({"--version"});
  const std::string out = testing::internal::GetCapturedStdout();
  EXPECT_NE(out.find("zlib "), std::string::npos) << out;
  EXPECT_EQ(out.find("libpng"), std::string::npos) << out;
  EXPECT_EQ(out.find("FFmpeg"), std::string::npos) << out;
}

TEST(Config, UnknownKeyOnCommandLine) {
  Params p;
  EXPECT_EQ(p.parseError({"--Bitz=3"}), "option --Bitz=3: unknown key 'Bitz' (did you mean Bits?)");
  EXPECT_EQ(p.parseError({"--Bitz"}), "option --Bitz: unknown key 'Bitz' (did you mean Bits?)");
  EXPECT_EQ(p.parseError({"--Bits"}), "option '--Bits' needs a value: --Bits=VALUE");
  EXPECT_EQ(p.parseError({"stray"}), "unknown argument 'stray' (see --help)");
}

TEST(Config, OutOfRangeValueNamesTheKey) {
  Params p;
  EXPECT_EQ(p.textError("Count : 5\nBits : 21\n"), "a.cfg:2: Bits: value 21 out of range [8, 20]");
  EXPECT_EQ(p.textError("Bits : 7\n"), "a.cfg:1: Bits: value 7 out of range [8, 20]");
  EXPECT_EQ(p.textError("Count : -1\n"), "a.cfg:1: Count: value -1 out of range [1, 1000]");
  EXPECT_EQ(p.textError("Rate : 0.25\n"), "a.cfg:1: Rate: value 0.25 out of range [0.5, 120]");
  EXPECT_EQ(p.parseError({"--Bits=99"}), "option --Bits=99: Bits: value 99 out of range [8, 20]");
  EXPECT_EQ(p.bits, 12);  // rejected values leave the field alone
  EXPECT_EQ(p.count, 5);  // lines before the bad one were applied
}

TEST(Config, BadValueNamesTheKey) {
  Params p;
  EXPECT_EQ(p.textError("Bits : ten\n"), "a.cfg:1: Bits: 'ten' is not an integer");
  EXPECT_EQ(p.textError("Bits : 10.5\n"), "a.cfg:1: Bits: '10.5' is not an integer");
  EXPECT_EQ(p.textError("Bits : 99999999999999999999\n"),
            "a.cfg:1: Bits: '99999999999999999999' is not an integer");
  EXPECT_EQ(p.textError("Rate : fast\n"), "a.cfg:1: Rate: 'fast' is not a number");
  EXPECT_EQ(p.textError("Rate : nan\n"), "a.cfg:1: Rate: 'nan' is not a number");
  EXPECT_EQ(p.textError("Rate : 25fps\n"), "a.cfg:1: Rate: '25fps' is not a number");
}

TEST(Config, MissingValue) {
  Params p;
  EXPECT_EQ(p.textError("Bits :\n"), "a.cfg:1: Bits: '' is not an integer");
  EXPECT_EQ(p.textError("Rate :   # nothing\n"), "a.cfg:1: Rate: '' is not a number");
  EXPECT_EQ(p.textError("Speed :\n"), "a.cfg:1: Speed: must be one of: slow | medium | fast");
  EXPECT_EQ(p.parseError({"--Bits"}), "option '--Bits' needs a value: --Bits=VALUE");
  EXPECT_EQ(p.parseError({"--Bits="}), "option --Bits=: Bits: '' is not an integer");
  EXPECT_EQ(p.parseError({"-c"}), "-c needs a cfg file name");
  // An empty string is a valid string value.
  p.table.parseText("Input :\n", "a.cfg");
  EXPECT_EQ(p.input, "");
}

TEST(Config, MalformedLines) {
  Params p;
  EXPECT_EQ(p.textError("Bits : 9\nBits 10\n"), "a.cfg:2: expected 'Key : value'");
  EXPECT_EQ(p.textError(": 10\n"), "a.cfg:1: missing key before ':'");
}

TEST(Config, MissingCfgFile) {
  TempDir dir("cfgmissing");
  const std::string path = dir.file("absent.cfg");
  Params p;
  const std::string message = p.parseError({"-c", path});
  EXPECT_EQ(message.rfind(path + ": cannot open", 0), 0u) << message;
}

TEST(Config, HelpListsEveryKeyWithItsDefault) {
  Params p;
  p.bits = 12;
  testing::internal::CaptureStdout();
  const bool proceed = p.parse({"--Bits=14", "--help", "--Bits=15"});
  const std::string help = testing::internal::GetCapturedStdout();
  EXPECT_FALSE(proceed);
  EXPECT_EQ(help, p.table.helpText());
  EXPECT_EQ(help.rfind("Usage: tool -c FILE [--Key=value ...]\n", 0), 0u) << help;
  const std::vector<std::string> lines = test::lines(help);
  // Key (and short flag) on one line with the meaning, default on the next.
  const std::vector<std::pair<std::string, std::string>> expected = {{"Input", "in.obj"},
                                                                     {"Count", "1"},
                                                                     {"Rate", "25"},
                                                                     {"Bits", "12"},
                                                                     {"Speed", "medium"},
                                                                     {"Verbose", "false"},
                                                                     {"Output (-o)", "(none)"},
                                                                     {"Trace (--trace)", "false"}};
  for (const auto& [key, value] : expected) {
    size_t i = 0;
    while (i < lines.size() && lines[i].rfind("  " + key + " ", 0) != 0)
      ++i;
    ASSERT_LT(i + 1, lines.size()) << key << " missing from:\n" << help;
    expectDefaultShown(lines[i + 1], value, key);
  }
  EXPECT_NE(help.find("grid bits [8..20]"), std::string::npos);
  EXPECT_NE(help.find("speed preset (slow | medium | fast)"), std::string::npos);
  EXPECT_NE(help.find("\nInput:\n"), std::string::npos);
  EXPECT_NE(help.find("\nCoding:\n"), std::string::npos);
  EXPECT_NE(help.find("\nOutput:\n"), std::string::npos);
  testing::internal::CaptureStdout();
  EXPECT_FALSE(p.parse({"-h"}));
  EXPECT_EQ(testing::internal::GetCapturedStdout(), help);
}

TEST(Config, EffectiveConfigIsAValidCfgFile) {
  Params p;
  ASSERT_TRUE(p.parse({"--Bits=17", "--Rate=59.94", "--Speed=slow", "-o", "x.3dvo", "--trace",
                       "--Input=dir/%03d.obj"}));
  const std::string effective = p.table.effectiveConfig();
  Params q;
  q.table.parseText(effective, "effective");
  EXPECT_EQ(q.bits, 17);
  EXPECT_EQ(q.rate, 59.94);
  EXPECT_EQ(q.speed, Speed::kSlow);
  EXPECT_EQ(q.output, "x.3dvo");
  EXPECT_TRUE(q.trace);
  EXPECT_EQ(q.input, "dir/%03d.obj");
  EXPECT_EQ(q.table.effectiveConfig(), effective);
}

TEST(Config, CommentsStartAtAHashAfterABlank) {
  Params p;
  p.table.parseText(
      "# a comment line\nInput : take#2/%03d.obj  # the second take\n"
      "Bits : 14 #no blank after the hash\nOutput : # no value\n",
      "a.cfg");
  EXPECT_EQ(p.input, "take#2/%03d.obj");
  EXPECT_EQ(p.bits, 14);
  EXPECT_EQ(p.output, "");
  EXPECT_EQ(p.textError("Bits : 14#c\n"), "a.cfg:1: Bits: '14#c' is not an integer");
}

TEST(Config, EffectiveConfigKeepsDerivedKeysUnset) {
  Params p;
  p.table.derivedWhenUnset("Bits", "chosen from the input");
  p.table.derivedWhenUnset("Count", "the input's length");
  ASSERT_TRUE(p.parse({"--Count=7"}));
  const std::string effective = p.table.effectiveConfig();
  // Unset and derived: a comment showing the default and why; set: a plain line.
  EXPECT_NE(effective.find("# Bits                     : 12  (not set: chosen from the input)\n"),
            std::string::npos)
      << effective;
  EXPECT_NE(effective.find("\nCount                    : 7\n"), std::string::npos) << effective;
  Params q;
  q.table.derivedWhenUnset("Bits", "chosen from the input");
  q.table.derivedWhenUnset("Count", "the input's length");
  q.table.parseText(effective, "effective");
  EXPECT_FALSE(q.table.wasSet("Bits"));
  EXPECT_TRUE(q.table.wasSet("Count"));
  EXPECT_EQ(q.count, 7);
  EXPECT_EQ(q.table.effectiveConfig(), effective);
}

TEST(Config, EffectiveConfigSaysWhatACfgLineCannotHold) {
  Params p;
  ASSERT_TRUE(p.parse({"--Input=take#2/%03d.obj", "--Output=a #b.3dvo"}));
  const std::string effective = p.table.effectiveConfig();
  EXPECT_EQ(effective.rfind("Input                    : take#2/%03d.obj\n", 0), 0u) << effective;
  EXPECT_NE(effective.find("\n# Output                   : 'a #b.3dvo'  (a cfg line cannot hold"),
            std::string::npos)
      << effective;
  for (const std::string value : {" lead", "trail ", "#first", "line\nbreak"}) {
    Params v;
    ASSERT_TRUE(v.parse({"--Input=" + value}));
    EXPECT_NE(v.table.effectiveConfig().find("# Input                    : '"), std::string::npos)
        << value;
  }
  Params q;
  q.table.parseText(effective, "effective");
  EXPECT_EQ(q.input, "take#2/%03d.obj");
  EXPECT_EQ(q.output, "");
}

TEST(Config, EncoderKeysRequiredByTheDesign) {
  EncoderParams params;
  OptionTable table("3dvo-enc", "usage");
  params.registerOptions(table);
  const std::string help = table.helpText();
  // The defaults listed are those of EncoderParams.
  const EncoderParams defaults;
  EXPECT_EQ(defaults.frameRate, 25.0);
  const std::vector<std::pair<std::string, std::string>> keys = {
      {"InputMeshPattern", "(none)"},
      {"FirstFrame", std::to_string(defaults.firstFrame)},
      {"FrameCount", std::to_string(defaults.frameCount)},
      {"FrameRate", "25"},
      {"GridBits", std::to_string(defaults.gridBits)},
      {"GOMSize", std::to_string(defaults.gomSize)},
      {"BitstreamFile (-o)", "(none)"},
      {"ReconMeshPattern", "(none)"}};
  const std::vector<std::string> lines = test::lines(help);
  for (const auto& [key, value] : keys) {
    size_t i = 0;
    while (i < lines.size() && lines[i].rfind("  " + key + " ", 0) != 0)
      ++i;
    ASSERT_LT(i + 1, lines.size()) << key << " missing from:\n" << help;
    expectDefaultShown(lines[i + 1], value, key);
  }
  // Every key of the effective configuration is documented in --help (the keys derived when
  // unset are printed as comments).
  for (std::string line : test::lines(table.effectiveConfig())) {
    if (line.rfind("# ", 0) == 0) line.erase(0, 2);
    const std::string key = line.substr(0, line.find(' '));
    EXPECT_NE(help.find("\n  " + key + " "), std::string::npos) << key;
  }
  const char* argv[] = {"3dvo-enc", "--GridBits=21"};
  try {
    table.parseCommandLine(2, argv);
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()),
              "option --GridBits=21: GridBits: value 21 out of range [8, 20]");
  }
}

TEST(Config, EncoderValidate) {
  EncoderParams params;
  try {
    params.validate();
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()),
              "InputMeshPattern is not set, nor a Dataset with meshes (see --help)");
  }
  params.inputMeshPattern = "in/%04d.obj";
  params.bitstreamFile = "x.3dvo";
  params.validate();
  params.reconMeshPattern = "recon.obj";
  EXPECT_THROW(params.validate(), Error);
}

}  // namespace
}  // namespace tdvo
