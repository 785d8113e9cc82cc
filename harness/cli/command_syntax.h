// What a command's help and reference say: its rows (each option or
// positional argument: name, value, help, default) and its text, and how
// they are written as the --help text and as Markdown
// (docs/command-line.md). The rows come from the command's option table
// (option_table.h), which also parses by them (parse_by_rows,
// command_line.h).
#pragma once

#include <cstddef>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

namespace hb {

/// One row as the parser and the texts see it (where its value goes is the
/// typed table's).
struct OptionSpec {
  std::string name;          ///< "--out"; a positional argument: its name, "RUN_DIR"
  std::string value_name;    ///< "DIR"; "LO HI": two values; empty: a flag
  std::string help;          ///< what it does: one paragraph
  std::string default_text;  ///< shown as "(default ...)"; empty: none said
  bool positional = false;
  bool repeatable = false;                   ///< an option that may come again, each value kept
  bool required = false;                     ///< an option without which the command does not run
  std::size_t min_count = 0, max_count = 1;  ///< a positional: how many values it takes
  std::string missing;  ///< a positional: what "missing ..." calls it; empty: its name

  /// Values after the option: the words of value_name.
  std::size_t arity() const;
  /// "--out DIR"; a positional: its name.
  std::string label() const;
};

/// Unbounded max_count of a positional.
inline constexpr std::size_t kAnyCount = std::numeric_limits<std::size_t>::max();

/// What a command's help says besides its rows.
struct CommandText {
  std::string name;                      ///< "compare"
  std::vector<std::string> description;  ///< paragraphs after the synopsis
  std::vector<std::string> notes;        ///< paragraphs after the option list
  std::vector<std::string> other_forms;  ///< more synopsis lines: "--explain"
};

/// A command's text and rows.
struct CommandSyntax {
  CommandText text;
  std::vector<OptionSpec> rows;
};

/// The --help text: "usage: hapticbench NAME ..." wrapped, the description,
/// the aligned list of arguments and options, the notes.
std::string usage_text(const CommandSyntax& syntax);
/// The synopsis lines alone ("hapticbench NAME ...", wrapped).
std::string synopsis_text(const CommandSyntax& syntax);
/// `text` wrapped to the help's width, ending with '\n': its first line
/// continues one already `column` wide, the others start with `indent` spaces.
std::string wrapped_text(const std::string& text, std::size_t column, std::size_t indent);
/// Rows as an aligned list, each line starting with `indent` spaces.
std::string option_list_text(const std::vector<OptionSpec>& rows, std::size_t indent);
/// The Markdown reference of a command: heading, summary, synopsis,
/// description, a table of the rows, notes.
std::string reference_markdown(const CommandSyntax& syntax, std::string_view summary);
/// Rows as a Markdown table (| argument | what it does | default |).
std::string markdown_option_table(const std::vector<OptionSpec>& rows);

}  // namespace hb
