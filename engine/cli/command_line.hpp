// The command line of every compaction program (compaction-run, -classify, -server, -worker),
// one grammar for all, CLI11 underneath:
//   --flag VALUE and --flag=VALUE; the last of a repeated flag wins;
//   numbers are read strictly: the whole text, decimal, finite (no "nan", "inf", hex or octal);
//   a problem is reported on stderr as "PROGRAM: --flag: message naming the value", exit 2;
//   -h/--help prints the help, --version "PROGRAM VERSION (REVISION)" (the engine's), exit 0.
// The help lists each flag with its value's name, its text, its range and its default (the
// bound variable's value when the flag is registered, unless a default text is given).
#pragma once

#include <deque>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "compaction/params.hpp"

namespace compaction::cli {

// Strict reading of a number from command-line text: the whole text must be the number, and a
// real must be finite.
bool parse_finite_real(std::string_view text, double& out);
bool parse_int(std::string_view text, long long& out);

// A problem with one flag's value, thrown by a custom flag's reader.
struct UsageError {
  std::string flag;
  std::string message;
};

class CommandLine {
 public:
  // `about`: the help's first paragraph; `usage`: the line after "usage: ".
  CommandLine(std::string program, std::string about, std::string usage);

  // A number in `range`; the message names the value when it is not one or out of range.
  void real(const std::string& flag, double& out, Range range, const std::string& value_name,
            const std::string& help);
  void integer(const std::string& flag, int& out, Range range, const std::string& value_name,
               const std::string& help);
  // Text; `non_empty` refuses "".
  void text(const std::string& flag, std::string& out, const std::string& value_name,
            const std::string& help, const std::string& default_text = {},
            bool non_empty = false);
  // One of `choices`.
  void choice(const std::string& flag, std::string& out, const std::vector<std::string>& choices,
              const std::string& value_name, const std::string& help);
  // A flag without a value.
  void flag(const std::string& flag, bool& out, const std::string& help);
  // A value read by `read`, which throws UsageError (or returns normally).
  void custom(const std::string& flag, std::function<void(const std::string&)> read,
              const std::string& value_name, const std::string& help,
              const std::string& default_text = {});
  // One positional argument (required when `required`).
  void positional(const std::string& name, std::string& out, const std::string& help,
                  bool required = true);
  // Every positional argument, in order (at least one when `required`); a program takes either
  // this or positional().
  void positionals(const std::string& name, std::vector<std::string>& out,
                   const std::string& help, bool required = true);
  // Paragraphs printed after the flags in --help.
  void notes(std::string text);

  // Parses argv and applies the values. std::nullopt: go on; otherwise the exit code (0 after
  // --help or --version, which are printed; 2 after a problem, which is reported).
  std::optional<int> parse(int argc, const char* const* argv);

  // Reports a problem found after parsing, as parse() does; returns the exit code 2.
  int fail(const std::string& flag, const std::string& message) const;

  std::string help() const;
  const std::string& program() const { return program_; }

 private:
  struct Entry {
    std::string flag, value_name, help, default_text;
    std::function<void(const std::string&)> read;  // empty for a flag without a value
    bool* set = nullptr;                            // a flag without a value
    std::string* positional = nullptr;
    std::vector<std::string>* positionals = nullptr;
    bool required = false;
    std::string raw;                // what CLI11 collected
    std::vector<std::string> raws;  // what CLI11 collected for positionals()
  };
  Entry& add(std::string flag, std::string value_name, std::string help, std::string default_text,
             std::function<void(const std::string&)> read);

  std::string program_, about_, usage_, notes_;
  std::deque<Entry> entries_;  // stable addresses: CLI11 writes into raw
};

}  // namespace compaction::cli
