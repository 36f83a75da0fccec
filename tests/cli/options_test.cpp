// Every subcommand's option table, read from CLI11 itself (app::addCommands):
// - each numeric option declares its range (app::inRange), and its boundary values (0, -1, just past
//   each end, NaN, infinities, a huge number) are refused by the command before any work: exit 2, one
//   line naming the option, nothing written; a count whose range takes 0 says in its help what 0 means;
// - its reference page (docs/cli/<name>.md) names every option, with its default where CLI11 has one.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "app/command.h"
#include "tests/test_util.h"

namespace isoatlas {
namespace {

namespace fs = std::filesystem;

struct Subcommand {
  CLI::App* app;
  std::string name;
};

// The command's tree as main.cpp builds it; `exitCode` outlives it (the callbacks hold it).
struct Command {
  int exitCode = 0;
  CLI::App app{"isoatlas"};
  Command() { app::addCommands(app, exitCode); }
  std::vector<Subcommand> subcommands() {
    std::vector<Subcommand> out;
    for (CLI::App* sub : app.get_subcommands({})) out.push_back({sub, sub->get_name()});
    return out;
  }
};

bool isHelp(const CLI::Option* o) { return o->get_name() == "--help" || o->get_name() == "--help-all"; }

// The option's range, read back from its "range" validator ("in [lo, hi]"); false when it has none.
bool rangeOf(CLI::Option* o, double& lo, double& hi) {
  try {
    const std::string d = o->get_validator("range")->get_description();
    return std::sscanf(d.c_str(), "in [%lf, %lf]", &lo, &hi) == 2;
  } catch (const CLI::OptionNotFound&) {
    return false;
  }
}

// CLI11's name of the option's value type, before any validator's text ("INT:in [...]" -> "INT").
std::string typeOf(const CLI::Option* o) {
  const std::string t = o->get_type_name();
  return t.substr(0, t.find(':'));
}
bool isNumeric(const CLI::Option* o) {
  const std::string t = typeOf(o);
  return t == "INT" || t == "UINT" || t == "FLOAT" || t == "NUMBER";
}
bool isInteger(const CLI::Option* o) { return typeOf(o) == "INT" || typeOf(o) == "UINT"; }

bool isTuple(const CLI::Option* o) { return o->get_type_name().starts_with("L FILE"); }

// The value of `o` on a command line: its text, and the rest its value needs (a tuple's file, the
// second of a pair of numbers).
std::string valueFor(const CLI::Option* o, const std::string& number, const fs::path& dir) {
  if (isTuple(o)) return number + " " + (dir / "level.ply").string();
  if (o->get_expected_min() == 2) return number + ",10";
  return number;
}

// `o` given `number` on a command line: --name=VALUE (so that CLI11 takes "-inf" as the value, not as
// short options), a tuple's values as words of their own.
std::string given(const CLI::Option* o, const std::string& number, const fs::path& dir) {
  if (o->get_positional()) return valueFor(o, number, dir);
  return o->get_name() + (isTuple(o) ? " " : "=") + valueFor(o, number, dir);
}

// What a required option or argument is given, so that a command line reaches the option under test:
// a file in the scratch folder (which need not exist: a refused value is refused before it is read),
// or a number inside the option's range.
std::string requiredValue(CLI::Option* o, const fs::path& dir) {
  double lo = 0, hi = 0;
  if (rangeOf(o, lo, hi)) return valueFor(o, lo <= 1 && 1 <= hi ? "1" : std::to_string(lo), dir);
  if (o->get_name() == "--at") return "1,1,1";
  if (o->get_name() == "--output") return (dir / "out.png").string();
  return (dir / ("in-" + o->get_name(true, false))).string();
}

std::string requiredArguments(CLI::App* sub, const CLI::Option* except, const fs::path& dir) {
  std::string args;
  for (CLI::Option* o : sub->get_options())
    // run's volume and -o too: never the demo's volume, nor a folder outside the scratch one.
    if (o != except && (o->get_required() || o->get_positional() || o->get_name() == "--output")) {
      const std::string value = requiredValue(o, dir);
      args += " " + (o->get_positional() ? value : o->get_name() + "=" + value);
    }
  return args;
}

struct Result {
  int code;
  std::string err;
};
Result runCommand(const std::string& args, const fs::path& logs) {
  static int calls = 0;
  const fs::path err = logs / ("stderr" + std::to_string(++calls));
  const std::string cmd = std::string(ISOATLAS_EXE) + " " + args + " >/dev/null 2>" + err.string() + " </dev/null";
  const int status = std::system(cmd.c_str());
  return {WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status), test::readBytes(err)};
}

std::string justPast(double end, bool below, bool integer) {
  const double step = integer ? 1 : std::max(std::abs(end) * 0.01, 1e-9);
  std::ostringstream s;
  s.precision(12);
  s << (below ? end - step : end + step);
  return s.str();
}

TEST(Options, EveryNumericOptionDeclaresItsRange) {
  Command command;
  int numeric = 0;
  for (const auto& [sub, name] : command.subcommands())
    for (CLI::Option* o : sub->get_options()) {
      double lo = 0, hi = 0;
      const bool ranged = rangeOf(o, lo, hi);
      if (isNumeric(o) || ranged) {
        ++numeric;
        EXPECT_TRUE(ranged) << name << " " << o->get_name() << ": a numeric option without app::inRange";
        EXPECT_LT(lo, hi) << name << " " << o->get_name();
        EXPECT_LT(hi, 1e300) << name << " " << o->get_name() << ": every count and length has an upper bound";
      }
    }
  EXPECT_GE(numeric, 40) << "the walk found too few numeric options: the table was not read";
}

// A count (an integer option) whose range takes 0 or -1 gives it a meaning in its help ("0: ...").
TEST(Options, ACountThatTakesZeroSaysWhatZeroMeans) {
  Command command;
  for (const auto& [sub, name] : command.subcommands())
    for (CLI::Option* o : sub->get_options()) {
      double lo = 0, hi = 0;
      if (!isInteger(o) || !rangeOf(o, lo, hi)) continue;
      for (const int v : {0, -1})
        if (lo <= v && v <= hi) {
          EXPECT_NE(o->get_description().find(std::to_string(v) + ":"), std::string::npos)
              << name << " " << o->get_name() << " takes " << v << " but its help does not say what it means";
        }
    }
}

// Each value at or past a range's ends: refused while parsing, exit 2, one line naming the option,
// nothing written. Values inside the range (a count's 0, say) are left to the command.
TEST(Options, BoundaryValuesAreRefusedBeforeAnyWork) {
  Command command;
  const fs::path dir = test::scratchDir();
  const fs::path work = dir / "work", logs = dir / "logs";
  fs::create_directories(work);
  fs::create_directories(logs);
  int tried = 0;
  for (const auto& [sub, name] : command.subcommands())
    for (CLI::Option* o : sub->get_options()) {
      double lo = 0, hi = 0;
      if (isHelp(o) || !rangeOf(o, lo, hi)) continue;
      const bool integer = isInteger(o);
      std::vector<std::string> values{"nan", "inf", "1e300", justPast(lo, true, integer), justPast(hi, false, integer)};
      if (!isTuple(o)) values.push_back("-inf");  // a tuple's first word cannot start with a letter after '-' 
      for (const double v : {0.0, -1.0})
        if (v < lo || v > hi) values.push_back(std::to_string(int(v)));
      for (const std::string& value : values) {
        const std::string args = name + requiredArguments(sub, o, work) + " " + given(o, value, work);
        const Result r = runCommand(args, logs);
        ++tried;
        EXPECT_EQ(r.code, 2) << args << "\n" << r.err;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << args << "\n" << r.err;
        EXPECT_NE(r.err.find(o->get_name()), std::string::npos) << args << ": the message does not name the option\n" << r.err;
        EXPECT_TRUE(fs::is_empty(work)) << args << " wrote into " << work;
        for (const auto& entry : fs::directory_iterator(work)) fs::remove_all(entry.path());
      }
    }
  EXPECT_GE(tried, 250);
}

// Within the range, a value is the command's to take: a count's 0 is not refused as out of range (the
// command then stops at its input, a file that is not there).
TEST(Options, AZeroACountTakesIsAccepted) {
  Command command;
  const fs::path dir = test::scratchDir();
  int tried = 0;
  for (const auto& [sub, name] : command.subcommands())
    for (CLI::Option* o : sub->get_options()) {
      double lo = 0, hi = 0;
      if (!isInteger(o) || !rangeOf(o, lo, hi) || lo > 0 || o->get_positional()) continue;
      const std::string args = name + requiredArguments(sub, o, dir) + " " + given(o, "0", dir);
      const Result r = runCommand(args, dir);
      ++tried;
      EXPECT_EQ(r.err.find(o->get_name() + ": '0'"), std::string::npos) << args << ": 0 was refused\n" << r.err;
    }
  EXPECT_GE(tried, 8);
}

// docs/cli/<name>.md: a row of its option table per option ("| `--name` | default | ..."), whose
// second cell holds the default CLI11 shows, in backticks (`1`, not 10).
std::vector<std::string> rowsNaming(const std::string& page, const std::string& option) {
  std::vector<std::string> rows;
  std::istringstream in(page);
  for (std::string line; std::getline(in, line);)
    if (line.starts_with("|")) {
      const std::size_t end = line.find('|', 1);
      if (end != std::string::npos && line.substr(0, end).find("`" + option + "`") != std::string::npos) rows.push_back(line);
    }
  return rows;
}
std::string cell(const std::string& row, int index) {
  std::size_t at = 0;
  for (int i = 0; i < index; ++i) at = row.find('|', at) + 1;
  return row.substr(at, row.find('|', at) - at);
}

TEST(Options, EachSubcommandsPageNamesEveryOptionAndItsDefault) {
  Command command;
  const fs::path docs = fs::path(ISOATLAS_SOURCE_DIR) / "docs" / "cli";
  const std::string index = test::readBytes(docs / "README.md");
  for (const auto& [sub, name] : command.subcommands()) {
    const fs::path page = docs / (name + ".md");
    ASSERT_TRUE(fs::exists(page)) << page << ": no reference page for isoatlas " << name;
    EXPECT_NE(index.find("(" + name + ".md)"), std::string::npos) << "docs/cli/README.md does not link " << name << ".md";
    const std::string text = test::readBytes(page);
    for (CLI::Option* o : sub->get_options()) {
      if (isHelp(o)) continue;
      const std::string option = o->get_positional() ? o->get_name(true, false) : o->get_name();
      const std::vector<std::string> rows = rowsNaming(text, option);
      ASSERT_EQ(rows.size(), 1u) << page << ": " << rows.size() << " rows of its option table name `" << option << "`";
      const std::string shown = o->get_default_str();
      if (!shown.empty() && shown != "[]") {
        EXPECT_NE(cell(rows[0], 2).find("`" + shown + "`"), std::string::npos)
            << page << ": `" << option << "`'s row does not give its default, " << shown << ": " << rows[0];
      }
    }
  }
}

}  // namespace
}  // namespace isoatlas
