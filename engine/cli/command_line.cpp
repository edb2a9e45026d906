#include "command_line.hpp"

#include <CLI/CLI.hpp>

#include <charconv>
#include <cmath>
#include <iostream>
#include <sstream>

#include "compaction/number_text.hpp"
#include "compaction/result.hpp"

namespace compaction::cli {

bool parse_finite_real(std::string_view text, double& out) {
  const char* end = text.data() + text.size();
  const auto [ptr, ec] = std::from_chars(text.data(), end, out);
  return !text.empty() && ec == std::errc() && ptr == end && std::isfinite(out);
}

bool parse_int(std::string_view text, long long& out) {
  const char* end = text.data() + text.size();
  const auto [ptr, ec] = std::from_chars(text.data(), end, out);
  return !text.empty() && ec == std::errc() && ptr == end;
}

namespace {

using text::num;

std::string quoted(const std::string& text) { return "'" + text + "'"; }

// "help, in [lo, hi]" for a number's help line.
std::string with_range(const std::string& help, const Range& r) {
  return help + (help.empty() ? "in " : ", in ") + to_string(r);
}

constexpr std::size_t kHelpColumn = 28;

}  // namespace

CommandLine::CommandLine(std::string program, std::string about, std::string usage)
    : program_(std::move(program)), about_(std::move(about)), usage_(std::move(usage)) {}

CommandLine::Entry& CommandLine::add(std::string flag, std::string value_name, std::string help,
                                     std::string default_text,
                                     std::function<void(const std::string&)> read) {
  Entry& e = entries_.emplace_back();
  e.flag = std::move(flag);
  e.value_name = std::move(value_name);
  e.help = std::move(help);
  e.default_text = std::move(default_text);
  e.read = std::move(read);
  return e;
}

void CommandLine::real(const std::string& flag, double& out, Range range,
                       const std::string& value_name, const std::string& help) {
  add(flag, value_name, with_range(help, range), num(out), [flag, &out, range](const std::string& v) {
         double d = 0;
         if (!parse_finite_real(v, d)) throw UsageError{flag, "expected a finite number, got " + quoted(v)};
         if (!range.contains(d)) throw UsageError{flag, "must be in " + to_string(range) + ", got " + v};
         out = d;
      });
}

void CommandLine::integer(const std::string& flag, int& out, Range range,
                          const std::string& value_name, const std::string& help) {
  add(flag, value_name, with_range(help, range), std::to_string(out),
      [flag, &out, range](const std::string& v) {
         long long n = 0;
         if (!parse_int(v, n)) throw UsageError{flag, "expected an integer, got " + quoted(v)};
         if (!range.contains(static_cast<double>(n))) {
           throw UsageError{flag, "must be in " + to_string(range) + ", got " + v};
         }
         out = static_cast<int>(n);
      });
}

void CommandLine::text(const std::string& flag, std::string& out, const std::string& value_name,
                       const std::string& help, const std::string& default_text,
                       bool non_empty) {
  add(flag, value_name, help, default_text, [flag, &out, non_empty](const std::string& v) {
         if (non_empty && v.empty()) throw UsageError{flag, "must not be empty"};
         out = v;
      });
}

void CommandLine::choice(const std::string& flag, std::string& out,
                         const std::vector<std::string>& choices, const std::string& value_name,
                         const std::string& help) {
  std::string list;
  for (const std::string& c : choices) {
    if (!list.empty()) list += '|';
    list += c;
  }
  add(flag, value_name, help + (help.empty() ? "" : ": ") + list, out,
      [flag, &out, choices, list](const std::string& v) {
         for (const std::string& c : choices) {
           if (v == c) {
             out = v;
             return;
           }
         }
         throw UsageError{flag, "expected " + list + ", got " + quoted(v)};
      });
}

void CommandLine::flag(const std::string& flag, bool& out, const std::string& help) {
  add(flag, "", help, "", {}).set = &out;
}

void CommandLine::custom(const std::string& flag, std::function<void(const std::string&)> read,
                         const std::string& value_name, const std::string& help,
                         const std::string& default_text) {
  add(flag, value_name, help, default_text, std::move(read));
}

void CommandLine::positional(const std::string& name, std::string& out, const std::string& help,
                             bool required) {
  Entry& e = add(name, "", help, "", {});
  e.positional = &out;
  e.required = required;
}

void CommandLine::positionals(const std::string& name, std::vector<std::string>& out,
                              const std::string& help, bool required) {
  Entry& e = add(name, "", help, "", {});
  e.positionals = &out;
  e.required = required;
}

void CommandLine::notes(std::string text) { notes_ = std::move(text); }

int CommandLine::fail(const std::string& flag, const std::string& message) const {
  std::cerr << program_ << ": " << flag << ": " << message << "\n";
  return 2;
}

std::string CommandLine::help() const {
  std::string s = program_ + ": " + about_ + "\n\nusage: " + program_ + " " + usage_ + "\n\n";
  auto line = [&s](std::string head, const std::string& text) {
    head = "  " + head;
    if (head.size() + 1 > kHelpColumn) {
      s += head + "\n";
      head.clear();
    }
    head.resize(kHelpColumn, ' ');
    std::size_t start = 0;
    for (;;) {  // the text's own lines, each indented to the column
      const std::size_t nl = text.find('\n', start);
      s += head + text.substr(start, nl - start) + "\n";
      if (nl == std::string::npos) break;
      head.assign(kHelpColumn, ' ');
      start = nl + 1;
    }
  };
  for (const Entry& e : entries_) {
    if (!e.positional && !e.positionals) continue;
    line(e.positionals ? e.flag + "..." : e.flag, e.help);
  }
  for (const Entry& e : entries_) {
    if (e.positional || e.positionals) continue;
    const std::string head = e.flag + (e.value_name.empty() ? "" : " " + e.value_name);
    line(head, e.help + (e.default_text.empty() ? "" : " [" + e.default_text + "]"));
  }
  line("--version", "print the engine version and source revision");
  line("-h, --help", "this text");
  if (!notes_.empty()) s += "\n" + notes_;
  if (!s.empty() && s.back() != '\n') s += '\n';
  return s;
}

std::optional<int> CommandLine::parse(int argc, const char* const* argv) {
  CLI::App app{about_, program_};
  app.set_help_flag();  // ours, below: printed with this class's layout
  app.allow_extras(true);
  app.option_defaults()->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
  bool help_asked = false, version_asked = false;
  app.add_flag("-h,--help", help_asked);
  app.add_flag("--version", version_asked);
  std::vector<std::pair<Entry*, CLI::Option*>> options;
  for (Entry& e : entries_) {
    CLI::Option* o = e.set           ? app.add_flag(e.flag)
                     : e.positionals ? app.add_option(e.flag, e.raws)
                                           ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll)
                                     : app.add_option(e.flag, e.raw);
    options.emplace_back(&e, o);
  }
  auto print_help = [this] {
    std::cout << help();
    return 0;
  };
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    for (int i = 1; i < argc; ++i) {
      if (std::string_view(argv[i]) == "-h" || std::string_view(argv[i]) == "--help") {
        return print_help();
      }
    }
    // A flag as the last argument: CLI11 says "--flag: 1 required TEXT missing".
    const std::string what = e.what();
    if (dynamic_cast<const CLI::ArgumentMismatch*>(&e) && what.find(':') != std::string::npos) {
      return fail(what.substr(0, what.find(':')), "needs a value");
    }
    std::cerr << program_ << ": " << what << "\n";
    return 2;
  }
  if (help_asked) return print_help();
  if (version_asked) {
    std::cout << program_ << " " << engine_version() << " (" << source_revision() << ")\n";
    return 0;
  }
  if (const auto extra = app.remaining(); !extra.empty()) {
    const std::string& first = extra.front();
    if (first.size() > 1 && first[0] == '-') {
      return fail(first.substr(0, first.find('=')), "unknown option (see --help)");
    }
    return fail(quoted(first), "unexpected argument (see --help)");
  }
  for (const auto& [e, o] : options) {
    if (o->count() == 0) {
      if (e->required) return fail(e->flag, "missing (see --help)");
      continue;
    }
    if (e->set) {
      *e->set = true;
    } else if (e->positional) {
      *e->positional = e->raw;
    } else if (e->positionals) {
      *e->positionals = e->raws;
    } else {
      try {
        e->read(e->raw);
      } catch (const UsageError& u) {
        return fail(u.flag, u.message);
      }
    }
  }
  return std::nullopt;
}

}  // namespace compaction::cli
