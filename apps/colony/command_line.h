// Command lines read with CLI11 (Debian libcli11-dev), as colony and
// colony_bench read theirs: `--opt value` and `--opt=value`, --help on the
// program and on every subcommand, and short errors that name the problem
// (with the closest option or command for a typo) instead of reprinting the
// usage. The caller prints a UsageError as
//   PROGRAM: MESSAGE
//   run 'PROGRAM [COMMAND] --help' for usage
// and exits with status 2.
#pragma once

#include <CLI/CLI.hpp>
#include <algorithm>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/text.h"

namespace colony::cli {

// A bad command line (exit status 2, nothing run).
struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// The value of option `option`: a whole number in [min, max], else a
// UsageError "OPTION: 'TEXT' is not accepted; expected a whole number in
// [MIN, MAX]".
inline long long ParseWhole(const std::string& option, const std::string& text, long long min,
                            long long max) {
  long long v = 0;
  const std::string problem = ParseWholeOption(option, text, min, max, v);
  if (!problem.empty()) throw UsageError(problem);
  return v;
}

// Help pages in 100 columns: CLI11's layout with descriptions wrapped at
// word boundaries (CLI11 2.1 does not wrap them).
class Formatter : public CLI::Formatter {
 public:
  static constexpr size_t kWidth = 100;
  std::string make_option_desc(const CLI::Option* opt) const override {
    return Wrap(CLI::Formatter::make_option_desc(opt), kWidth - get_column_width());
  }
  std::string make_description(const CLI::App* app) const override {
    const std::string text = app->get_description();
    return text.empty() ? "" : Wrap(text, kWidth) + "\n";
  }
  std::string make_subcommand(const CLI::App* sub) const override {
    std::stringstream out;
    CLI::detail::format_help(out, sub->get_display_name(true),
                             Wrap(sub->get_description(), kWidth - get_column_width()),
                             get_column_width());
    return out.str();
  }

 private:
  // `text` in lines of at most `width` characters (a longer word stays whole).
  static std::string Wrap(const std::string& text, size_t width) {
    std::string out;
    size_t line = 0;  // characters on the current line
    std::istringstream words(text);
    for (std::string word; words >> word;) {
      if (line > 0 && line + 1 + word.size() > width) {
        out += '\n';
        line = 0;
      } else if (line > 0) {
        out += ' ';
        ++line;
      }
      out += word;
      line += word.size();
    }
    return out;
  }
};

// The house style of help pages: "usage:", wrapped descriptions, the option
// column wide enough for "--set PATH=VALUE". Call before adding
// subcommands, which inherit it.
inline void SetUpHelp(CLI::App& app) {
  auto formatter = std::make_shared<Formatter>();
  formatter->label("Usage", "usage");
  formatter->column_width(28);
  app.formatter(formatter);
  app.set_help_flag("-h,--help", "prints this help");
  // An option given twice: the last one counts (options holding lists say
  // otherwise).
  app.option_defaults()->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
}

// An option that may be given many times, one value each ("--set A=1 --set
// B=2"); words after it are not taken as more values.
inline CLI::Option* AddListOption(CLI::App& app, const std::string& name,
                                  std::vector<std::string>& values, const std::string& help) {
  return app.add_option(name, values, help)
      ->allow_extra_args(false)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
}

namespace detail {

// "-x", "--xyz", "--xyz=1"; not "-1", "-.5", "-" or "--".
inline bool LooksLikeOption(const std::string& word) {
  return word.size() > 1 && word[0] == '-' && !(word[1] >= '0' && word[1] <= '9') &&
         word[1] != '.' && word != "--";
}

// "unknown option '--seeed'; did you mean '--seed'?"
inline std::string UnknownOption(const CLI::App& app, const std::string& word) {
  const std::string name = word.substr(0, word.find('='));
  std::vector<std::string> known;
  for (const CLI::Option* o : app.get_options()) {
    for (const auto& n : o->get_lnames()) known.push_back("--" + n);
    for (const auto& n : o->get_snames()) known.push_back("-" + n);
  }
  std::string guess;
  if (name.size() == 2) {
    // "-q": the one long option that starts with that letter, if any.
    for (const auto& k : known) {
      if (k.compare(0, 3, "--" + name.substr(1)) != 0) continue;
      guess = guess.empty() ? k : "-";
    }
    if (guess == "-") guess.clear();
  } else {
    guess = DidYouMean(name, known);
  }
  return "unknown option '" + name + "'" + (guess.empty() ? "" : "; did you mean '" + guess + "'?");
}

// "unknown command 'rnu'; did you mean 'run'?"
inline std::string UnknownCommand(const CLI::App& app, const std::string& word) {
  std::vector<std::string> known;
  for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; }))
    known.push_back(sub->get_name());
  const std::string guess = DidYouMean(word, known);
  return "unknown command '" + word + "'" +
         (guess.empty() ? "; the commands are " + Join(known) : "; did you mean '" + guess + "'?");
}

// CLI11's message for a missing value is "--seed: 1 required TEXT missing".
inline std::string ShortMessage(const CLI::ParseError& e) {
  const std::string what = e.what();
  const size_t colon = what.find(": ");
  if (dynamic_cast<const CLI::ArgumentMismatch*>(&e) && colon != std::string::npos &&
      what.find(" required ", colon) != std::string::npos &&
      what.compare(what.size() - 8, 8, " missing") == 0) {
    return what.substr(0, colon) + " needs a value";
  }
  return what;
}

}  // namespace detail

// The subcommand chosen on the command line, the deepest one (or `app`).
inline CLI::App& Chosen(CLI::App& app) {
  CLI::App* at = &app;
  while (!at->get_subcommands().empty()) at = at->get_subcommands().front();
  return *at;
}

// Parses `args` (the words after the program's name) into `app` and its
// subcommands, each made with allow_extras() so that what they do not know is
// reported here. Returns false when --help or --version was given (and
// printed to standard output: the program ends with status 0). Throws
// UsageError for an unknown option, an unknown command, a missing value or
// another CLI11 error. Words that are not options and that no positional
// took stay in Chosen(app).remaining(), for the caller to judge.
inline bool Parse(CLI::App& app, std::vector<std::string> args) {
  std::reverse(args.begin(), args.end());  // CLI11 takes them last first
  try {
    app.parse(args);
  } catch (const CLI::Success& e) {  // --help, --version
    app.exit(e);
    return false;
  } catch (const CLI::ParseError& e) {
    throw UsageError(detail::ShortMessage(e));
  }
  for (const CLI::App* at = &app;;) {
    for (const auto& word : at->remaining()) {
      if (detail::LooksLikeOption(word)) throw UsageError(detail::UnknownOption(*at, word));
    }
    if (at->get_subcommands().empty()) break;
    at = at->get_subcommands().front();
  }
  // A word where a command was expected.
  const bool has_commands = !app.get_subcommands([](const CLI::App*) { return true; }).empty();
  if (has_commands && app.get_subcommands().empty() && !app.remaining().empty()) {
    throw UsageError(detail::UnknownCommand(app, app.remaining().front()));
  }
  return true;
}

}  // namespace colony::cli
