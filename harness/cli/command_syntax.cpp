#include "harness/cli/command_syntax.h"

#include <algorithm>
#include <cctype>
#include <sstream>

namespace hb {

namespace {

/// The help text's width: lines are wrapped before it.
constexpr std::size_t kTextWidth = 92;
/// Labels up to this wide share their line with the help; longer ones
/// stand on a line of their own.
constexpr std::size_t kLabelWidth = 20;

std::string bracketed(const std::string& text) {
  std::string out = "[";
  out += text;
  out += ']';
  return out;
}

// A row as the synopsis writes it: "BASELINE", "[RUN_DIR...]", "[--out DIR]",
// "[--algo NAME]...", "--label LABEL".
std::string synopsis_item(const OptionSpec& row) {
  if (row.positional) {
    const std::string many = row.max_count > 1 ? row.name + "..." : row.name;
    return row.min_count == 0 ? bracketed(many) : many;
  }
  const std::string label = row.required ? row.label() : bracketed(row.label());
  return row.repeatable ? label + "..." : label;
}

// The help of a row with its default and whether it repeats.
std::string full_help(const OptionSpec& row) {
  std::string help = row.help;
  if (!row.default_text.empty()) help += " (default " + row.default_text + ")";
  if (row.repeatable) help += " (repeatable)";
  return help;
}

// `words` wrapped to kTextWidth, never split: the first line continues
// `out` (already `column` wide), the others start with `indent` spaces.
void wrap_words(std::string& out, std::size_t column, const std::vector<std::string>& words,
                std::size_t indent) {
  bool first = true;
  for (const std::string& word : words) {
    if (!first && column + 1 + word.size() > kTextWidth) {
      out += '\n';
      out.append(indent, ' ');
      column = indent;
    } else if (!first) {
      out += ' ';
      ++column;
    }
    out += word;
    column += word.size();
    first = false;
  }
  out += '\n';
}

void wrap_into(std::string& out, std::size_t column, const std::string& text, std::size_t indent) {
  std::istringstream in(text);
  std::vector<std::string> words;
  for (std::string word; in >> word;) words.push_back(word);
  wrap_words(out, column, words, indent);
}

// The synopsis: `first` before the first line, `other` before each other
// form, continuation lines aligned after the command's name.
std::string synopsis_lines(const CommandSyntax& syntax, const std::string& first,
                           const std::string& other) {
  // Positionals, then the options a run needs, then the others.
  std::vector<std::string> items;
  for (const int pass : {0, 1, 2})
    for (const OptionSpec& row : syntax.rows)
      if ((pass == 0 && row.positional) || (pass == 1 && !row.positional && row.required) ||
          (pass == 2 && !row.positional && !row.required))
        items.push_back(synopsis_item(row));
  const std::string command = "hapticbench " + syntax.text.name;
  std::string out = first + command;
  if (!items.empty()) out += ' ';
  wrap_words(out, out.size(), items, first.size() + command.size() + 1);
  for (const std::string& form : syntax.text.other_forms)
    out += other + command + " " + form + "\n";
  return out;
}

void paragraphs_into(std::string& out, const std::vector<std::string>& paragraphs) {
  for (const std::string& paragraph : paragraphs) {
    out += "  ";
    wrap_into(out, 2, paragraph, 2);
  }
}

// Markdown text: '|' escaped everywhere (a table cell), and outside code
// spans the characters Markdown would take for markup.
std::string markdown_escaped(const std::string& text) {
  std::string out;
  bool code = false;
  for (const char c : text) {
    if (c == '`') code = !code;
    if (c == '|' || (!code && (c == '<' || c == '*' || c == '\\'))) out += '\\';
    out += c;
  }
  return out;
}

// A summary as a sentence: capitalised, ending with a full stop.
std::string sentence(std::string_view summary) {
  std::string text(summary);
  if (!text.empty()) text[0] = static_cast<char>(std::toupper(static_cast<unsigned char>(text[0])));
  if (!text.empty() && text.back() != '.') text += '.';
  return text;
}

}  // namespace

std::size_t OptionSpec::arity() const {
  std::istringstream words(value_name);
  std::size_t count = 0;
  for (std::string word; words >> word;) ++count;
  return positional ? 1 : count;
}

std::string OptionSpec::label() const {
  return value_name.empty() || positional ? name : name + " " + value_name;
}

std::string wrapped_text(const std::string& text, std::size_t column, std::size_t indent) {
  std::string out;
  wrap_into(out, column, text, indent);
  return out;
}

std::string synopsis_text(const CommandSyntax& syntax) { return synopsis_lines(syntax, "", ""); }

std::string option_list_text(const std::vector<OptionSpec>& rows, std::size_t indent) {
  std::size_t width = 0;
  for (const OptionSpec& row : rows)
    if (row.label().size() <= kLabelWidth) width = std::max(width, row.label().size());
  const std::size_t column = indent + width + 2;
  std::string out;
  for (const OptionSpec& row : rows) {
    const std::string label = row.label();
    out += std::string(indent, ' ') + label;
    if (label.size() > width)
      out.append(1, '\n').append(column, ' ');
    else
      out += std::string(column - indent - label.size(), ' ');
    wrap_into(out, column, full_help(row), column);
  }
  return out;
}

std::string usage_text(const CommandSyntax& syntax) {
  std::string out = synopsis_lines(syntax, "usage: ", "       ");
  paragraphs_into(out, syntax.text.description);
  out += option_list_text(syntax.rows, 2);
  paragraphs_into(out, syntax.text.notes);
  return out;
}

std::string markdown_option_table(const std::vector<OptionSpec>& rows) {
  std::string out = "| argument | what it does | default |\n| --- | --- | --- |\n";
  for (const OptionSpec& row : rows) {
    std::string help = row.help;
    if (row.repeatable) help += " (repeatable)";
    if (row.required) help += " (required)";
    out += "| `" + markdown_escaped(row.label()) + "` | " + markdown_escaped(help) + " | " +
           markdown_escaped(row.default_text) + " |\n";
  }
  return out;
}

std::string reference_markdown(const CommandSyntax& syntax, std::string_view summary) {
  std::vector<std::string> blocks = {"## hapticbench " + syntax.text.name,
                                     markdown_escaped(sentence(summary)),
                                     "```text\n" + synopsis_text(syntax) + "```"};
  for (const std::string& paragraph : syntax.text.description)
    blocks.push_back(markdown_escaped(paragraph));
  if (!syntax.rows.empty()) {
    blocks.push_back(markdown_option_table(syntax.rows));
    blocks.back().pop_back();  // its last line's end
  }
  for (const std::string& paragraph : syntax.text.notes)
    blocks.push_back(markdown_escaped(paragraph));
  std::string out;
  for (const std::string& block : blocks) out += (out.empty() ? "" : "\n\n") + block;
  return out + "\n";
}

}  // namespace hb
