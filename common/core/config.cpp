#include "common/core/config.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "common/core/error.h"
#include "common/core/file_io.h"
#include "common/core/number_text.h"
#include "common/core/text_tokens.h"
#include "common/core/version.h"

namespace tdvo {

namespace {

std::string trim(const std::string& s) {
  size_t b = s.find_first_not_of(" \t\r");
  if (b == std::string::npos) return "";
  size_t e = s.find_last_not_of(" \t\r");
  return s.substr(b, e - b + 1);
}

// Edit distance between a and b (insertions, deletions, substitutions and swaps of two
// neighbouring characters each cost 1), ignoring case: how far a mistyped key is from a real one.
size_t editDistance(const std::string& a, const std::string& b) {
  auto lower = [](char c) { return (c >= 'A' && c <= 'Z') ? static_cast<char>(c - 'A' + 'a') : c; };
  const size_t n = a.size(), m = b.size();
  std::vector<std::vector<size_t>> d(n + 1, std::vector<size_t>(m + 1));
  for (size_t i = 0; i <= n; ++i)
    d[i][0] = i;
  for (size_t j = 0; j <= m; ++j)
    d[0][j] = j;
  for (size_t i = 1; i <= n; ++i)
    for (size_t j = 1; j <= m; ++j) {
      const size_t cost = lower(a[i - 1]) == lower(b[j - 1]) ? 0 : 1;
      d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + cost});
      if (i > 1 && j > 1 && lower(a[i - 1]) == lower(b[j - 2]) &&
          lower(a[i - 2]) == lower(b[j - 1]))
        d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
    }
  return d[n][m];
}

// Where the comment of a cfg line starts: at a '#' that begins the line or follows a blank
// (npos: no comment).
size_t commentStart(const std::string& line) {
  for (size_t i = 0; i < line.size(); ++i)
    if (line[i] == '#' && (i == 0 || line[i - 1] == ' ' || line[i - 1] == '\t')) return i;
  return std::string::npos;
}

// True when `Key : value` read back by parseText gives `value` again.
bool cfgLineHolds(const std::string& value) {
  return value.find('\n') == std::string::npos && trim(value) == value &&
         commentStart(" " + value) == std::string::npos;
}

}  // namespace

void OptionTable::section(const std::string& title) {
  currentSection_ = title;
}

OptionTable::Option& OptionTable::addOption(const std::string& key, const std::string& help) {
  if (find(key)) throw std::logic_error("option " + key + " added twice");
  Option o;
  o.key = key;
  o.help = help;
  o.section = currentSection_;
  options_.push_back(std::move(o));
  return options_.back();
}

void OptionTable::add(const std::string& key, std::string& field, const std::string& help,
                      const std::string& shortFlag) {
  Option& o = addOption(key, help);
  o.shortFlag = shortFlag;
  o.parse = [&field](const std::string& v) { field = v; };
  o.print = [&field]() { return field; };
  o.defaultValue = field;
}

void OptionTable::add(const std::string& key, int& field, int min, int max,
                      const std::string& help) {
  Option& o = addOption(key, help + " [" + std::to_string(min) + ".." + std::to_string(max) + "]");
  o.parse = [&field, min, max](const std::string& v) {
    long long value = 0;
    auto [ptr, ec] = std::from_chars(v.data(), v.data() + v.size(), value);
    if (v.empty() || ec != std::errc() || ptr != v.data() + v.size())
      throw std::string("'" + v + "' is not an integer");
    if (value < min || value > max)
      throw std::string("value " + v + " out of range [" + std::to_string(min) + ", " +
                        std::to_string(max) + "]");
    field = static_cast<int>(value);
  };
  o.print = [&field]() { return std::to_string(field); };
  o.defaultValue = o.print();
}

void OptionTable::add(const std::string& key, double& field, double min, double max,
                      const std::string& help) {
  Option& o = addOption(key, help + " [" + formatDouble(min) + ".." + formatDouble(max) + "]");
  o.parse = [&field, min, max](const std::string& v) {
    double value = 0;
    auto [ptr, ec] = std::from_chars(v.data(), v.data() + v.size(), value);
    if (v.empty() || ec != std::errc() || ptr != v.data() + v.size() || !std::isfinite(value))
      throw std::string("'" + v + "' is not a number");
    if (value < min || value > max)
      throw std::string("value " + v + " out of range [" + formatDouble(min) + ", " +
                        formatDouble(max) + "]");
    field = value;
  };
  o.print = [&field]() { return formatDouble(field); };
  o.defaultValue = o.print();
}

void OptionTable::add(const std::string& key, bool& field, const std::string& help,
                      const std::string& shortFlag) {
  Option& o = addOption(key, help + " (true | false)");
  o.shortFlag = shortFlag;
  o.isBool = true;
  o.parse = [&field](const std::string& v) {
    if (v == "1" || v == "true" || v == "yes")
      field = true;
    else if (v == "0" || v == "false" || v == "no")
      field = false;
    else
      throw std::string("'" + v + "' is not a boolean (true/false, 1/0, yes/no)");
  };
  o.print = [&field]() { return std::string(field ? "true" : "false"); };
  o.defaultValue = o.print();
}

OptionTable::Option* OptionTable::find(const std::string& key) {
  for (Option& o : options_)
    if (o.key == key) return &o;
  return nullptr;
}

const OptionTable::Option* OptionTable::find(const std::string& key) const {
  for (const Option& o : options_)
    if (o.key == key) return &o;
  return nullptr;
}

void OptionTable::set(const std::string& key, const std::string& value, const std::string& origin) {
  Option* o = find(key);
  if (!o) {
    const std::string near = closestKey(key);
    throw Error(origin + ": unknown key '" + key + "' (" +
                (near.empty() ? std::string("see --help") : "did you mean " + near + "?") + ")");
  }
  try {
    o->parse(value);
  } catch (const std::string& message) {
    throw Error(origin + ": " + key + ": " + message);
  }
  o->set = true;
}

std::string OptionTable::closestKey(const std::string& key) const {
  // A key is suggested when it is within a third of its length of what was typed (at least 1,
  // at most 3 edits) and no other key is as near.
  const size_t limit = std::clamp<size_t>(key.size() / 3, 1, 3);
  std::string best;
  size_t bestDistance = limit + 1;
  bool tie = false;
  for (const Option& o : options_) {
    const size_t d = editDistance(key, o.key);
    if (d < bestDistance) {
      best = o.key;
      bestDistance = d;
      tie = false;
    } else if (d == bestDistance) {
      tie = true;
    }
  }
  return tie ? std::string() : best;
}

bool OptionTable::wasSet(const std::string& key) const {
  const Option* o = find(key);
  return o && o->set;
}

void OptionTable::derivedWhenUnset(const std::string& key, const std::string& how, bool fallsBack) {
  Option* o = find(key);
  if (!o) throw std::logic_error("derivedWhenUnset: no option " + key);
  o->derivedHow = how;
  o->fallsBack = fallsBack;
}

void OptionTable::parseText(const std::string& text, const std::string& origin) {
  // A UTF-8 byte-order mark (as some Windows editors write) is not part of the first key.
  std::istringstream in(std::string(withoutUtf8Bom(text)));
  std::string line;
  int lineNumber = 0;
  while (std::getline(in, line)) {
    ++lineNumber;
    const std::string where = origin + ":" + std::to_string(lineNumber);
    const size_t hash = commentStart(line);
    if (hash != std::string::npos) line = line.substr(0, hash);
    line = trim(line);
    if (line.empty()) continue;
    size_t colon = line.find(':');
    if (colon == std::string::npos) throw Error(where + ": expected 'Key : value'");
    const std::string key = trim(line.substr(0, colon));
    if (key.empty()) throw Error(where + ": missing key before ':'");
    set(key, trim(line.substr(colon + 1)), where);
  }
}

void OptionTable::parseFile(const std::string& path) {
  filesRead_.push_back(path);
  parseText(readTextFile(path, kMaxCfgFileBytes, "a cfg file"), path);
}

void OptionTable::addVersionLines(const std::vector<std::string>& lines) {
  versionLines_.insert(versionLines_.end(), lines.begin(), lines.end());
}

bool OptionTable::parseCommandLine(int argc, const char* const* argv) {
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "-h" || arg == "--help") {
      std::fputs(helpText().c_str(), stdout);
      return false;
    }
    if (arg == "--version") {
      std::string text = programName_ + " (3DVO " + releaseVersion() + ")\n";
      for (const std::string& line : versionLines_)
        text += "  " + line + "\n";
      for (const std::string& line : coreLibraryVersions())
        text += "  " + line + "\n";
      std::fputs(text.c_str(), stdout);
      return false;
    }
    if (arg == "-c") {
      if (i + 1 >= argc) throw Error("-c needs a cfg file name");
      parseFile(argv[++i]);
      continue;
    }
    bool matched = false;
    for (Option& o : options_) {
      // A long alias also takes its value after '=' (--verify=FILE, as --verify FILE).
      const std::string withValue = o.shortFlag + "=";
      if (!o.isBool && o.shortFlag.rfind("--", 0) == 0 && arg.rfind(withValue, 0) == 0) {
        set(o.key, arg.substr(withValue.size()), "option " + arg);
        matched = true;
        break;
      }
      if (!o.shortFlag.empty() && o.shortFlag == arg) {
        if (o.isBool) {
          set(o.key, "true", "option " + arg);
        } else {
          if (i + 1 >= argc) throw Error(arg + " needs a value");
          set(o.key, argv[++i], "option " + arg);
        }
        matched = true;
        break;
      }
    }
    if (matched) continue;
    if (arg.rfind("--", 0) == 0) {
      size_t eq = arg.find('=');
      const std::string key = arg.substr(2, eq == std::string::npos ? std::string::npos : eq - 2);
      const Option* o = find(key);
      if (eq == std::string::npos) {
        if (!o) set(key, "true", "option " + arg);  // throws: unknown key
        if (!o->isBool) throw Error("option '" + arg + "' needs a value: --" + key + "=VALUE");
        set(key, "true", "option " + arg);
      } else {
        set(key, arg.substr(eq + 1), "option " + arg);
      }
      continue;
    }
    throw Error("unknown argument '" + arg + "' (see --help)");
  }
  return true;
}

std::string OptionTable::helpText() const {
  std::string out = "Usage: " + usage_ + "\n\n";
  out += "  -c FILE          read a cfg file (Key : value lines); may be repeated, later wins\n";
  out += "  --Key=VALUE      set one key; applied in order with the -c files\n";
  out += "  -h, --help       print this help\n";
  out += "  --version        print the 3DVO, stream syntax and library versions\n";
  std::string section;
  for (const Option& o : options_) {
    if (o.section != section) {
      section = o.section;
      out += "\n" + section + ":\n";
    }
    std::string name = "  " + o.key;
    if (!o.shortFlag.empty()) name += " (" + o.shortFlag + ")";
    if (name.size() < 26) name.resize(26, ' ');
    // A key the program derives while it is unset has no fixed default: how it is derived is
    // what the user gets.
    const std::string value = o.defaultValue.empty() ? "(none)" : o.defaultValue;
    out += name + " " + o.help + "\n" + std::string(27, ' ') + "default: " +
           (o.derivedHow.empty()
                ? value
                : "not set (" + o.derivedHow + (o.fallsBack ? "; else " + value : "") + ")") +
           "\n";
  }
  return out;
}

std::string OptionTable::effectiveConfig() const {
  std::string out;
  for (const Option& o : options_) {
    std::string key = o.key;
    if (key.size() < 24) key.resize(24, ' ');
    const std::string value = o.print();
    if (!o.set && !o.derivedHow.empty()) {
      out += "# " + key + " : " + value + "  (not set: " + o.derivedHow + ")\n";
    } else if (!cfgLineHolds(value)) {
      // Shown as the error messages show a value (common/core/error.h), on one line.
      out += "# " + key + " : '" + oneLine(value) + "'" +
             "  (a cfg line cannot hold this value; it can be given on the command line)\n";
    } else {
      out += key + " : " + value + "\n";
    }
  }
  return out;
}

}  // namespace tdvo
