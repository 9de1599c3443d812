// HM/VTM-style configuration: an option table bound to the fields of a parameter struct.
//
//   app -c cfg/a.cfg -c cfg/seq.cfg --QP=28
//
// Files hold `Key : value  # comment` lines (a comment starts at a '#' that begins the line or
// follows a space or tab, so a value such as take#2/%03d.obj keeps its '#'). Files and
// --Key=value options are applied in the order given, so later ones win. Unknown keys and bad
// values are errors that name the file and line (or the command-line option) and the key.
// --help prints every key with its default and meaning, by section.
#pragma once

#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace tdvo {

class OptionTable {
 public:
  explicit OptionTable(std::string programName, std::string usage)
      : programName_(std::move(programName)), usage_(std::move(usage)) {}

  // Starts a new section of the --help listing.
  void section(const std::string& title);

  // Binds a key to a field. The field's current value is the default. `shortFlag` (e.g. "-i")
  // is an optional alias on the command line taking the next argument as its value.
  void add(const std::string& key, std::string& field, const std::string& help,
           const std::string& shortFlag = "");
  void add(const std::string& key, int& field, int min, int max, const std::string& help);
  void add(const std::string& key, double& field, double min, double max, const std::string& help);
  // Booleans take true/false, 1/0, yes/no; a bare --Key (or the short flag) means true.
  void add(const std::string& key, bool& field, const std::string& help,
           const std::string& shortFlag = "");
  // An enumeration: one of the listed names.
  template <class E>
  void addEnum(const std::string& key, E& field, std::vector<std::pair<std::string, E>> names,
               const std::string& help);

  // Lines --version prints after the release and the core libraries (common/core/version.h): the
  // stream syntax version and the libraries only this app links (Draco, x264, OpenMesh ...).
  void addVersionLines(const std::vector<std::string>& lines);

  // Applies the command line. Returns false when --help or --version was asked for (the text
  // has then been printed to stdout and the caller should exit 0). Throws Error on any bad
  // option.
  bool parseCommandLine(int argc, const char* const* argv);

  // Applies one cfg file / one text of cfg lines (`origin` names it in error messages).
  void parseFile(const std::string& path);
  void parseText(const std::string& text, const std::string& origin);

  // Sets one key from a string; `origin` names where the value came from.
  void set(const std::string& key, const std::string& value, const std::string& origin);

  // True when the key was set by a file or an option (not left at its default).
  bool wasSet(const std::string& key) const;

  // Marks a key whose value the program derives at run time when no file or option sets it
  // (from other keys or from the input; `how` says how, e.g. "chosen by Quality"): its being
  // set changes what the program does, so effectiveConfig() prints it, while unset, as a
  // comment, and the printed configuration read back leaves it unset too. --help shows the
  // default as "not set (how; else DEFAULT)", or "not set (how)" when `fallsBack` is false (the
  // default is never used).
  void derivedWhenUnset(const std::string& key, const std::string& how, bool fallsBack = true);

  // The cfg files read so far (-c and parseFile), in order: inputs no output may overwrite.
  const std::vector<std::string>& filesRead() const { return filesRead_; }

  std::string helpText() const;
  // Every key with its value, one `Key : value` line each: a cfg file that, read back, sets
  // every key as this table has it. Two kinds of line are comments (`# Key : value  (why)`):
  // a key derivedWhenUnset and not set (its default shown; the program derives the value it
  // uses), and a value a cfg line cannot hold (a newline, surrounding blanks, or a '#' after a
  // blank), which only the command line can give.
  std::string effectiveConfig() const;

 private:
  struct Option {
    std::string key, shortFlag, help, defaultValue, section;
    std::string derivedHow;  // derivedWhenUnset: how the value is derived when not set
    bool fallsBack = true;   // derivedWhenUnset: the default is used where nothing is derived
    bool isBool = false;
    bool set = false;
    std::function<void(const std::string&)> parse;  // throws std::string message on bad value
    std::function<std::string()> print;
  };
  Option& addOption(const std::string& key, const std::string& help);
  Option* find(const std::string& key);
  // The registered key nearest to a mistyped `key`, or "" when none is near enough.
  std::string closestKey(const std::string& key) const;
  const Option* find(const std::string& key) const;

  std::string programName_, usage_, currentSection_;
  std::vector<std::string> versionLines_;
  std::vector<Option> options_;
  std::vector<std::string> filesRead_;
};

// Implementation detail of addEnum, kept here so any enum type works.
template <class E>
void OptionTable::addEnum(const std::string& key, E& field,
                          std::vector<std::pair<std::string, E>> names, const std::string& help) {
  std::string list;
  for (const auto& n : names)
    list += (list.empty() ? "" : " | ") + n.first;
  Option& o = addOption(key, help + " (" + list + ")");
  auto namesCopy = names;
  o.parse = [&field, namesCopy, list](const std::string& v) {
    for (const auto& n : namesCopy)
      if (n.first == v) {
        field = n.second;
        return;
      }
    throw std::string("must be one of: " + list);
  };
  o.print = [&field, namesCopy]() {
    for (const auto& n : namesCopy)
      if (n.second == field) return n.first;
    return std::string("?");
  };
  o.defaultValue = o.print();
}

}  // namespace tdvo
