// `hapticbench generate`: runs a synthetic trace generator and writes the
// trace as hapticbench CSV with its JSON sidecar.
#include <cmath>
#include <exception>
#include <filesystem>
#include <iostream>
#include <string>
#include <string_view>
#include <vector>

#include "hapticbench/input_error.h"
#include "hapticbench/param_set.h"
#include "harness/cli/command_line.h"
#include "harness/cli/commands.h"
#include "harness/cli/option_table.h"
#include "harness/output/output_ownership.h"
#include "harness/trace/generators.h"
#include "harness/trace/trace.h"

namespace hb {

namespace {

/// "0.5" -> number, "0,0,0.03" -> list, "true"/"false" -> flag, else string.
ParamValue parse_param_value(const std::string& text) {
  if (text == "true") return true;
  if (text == "false") return false;
  if (const std::optional<double> number = parse_number(text)) return *number;
  if (text.find(',') != std::string::npos) {
    std::vector<double> list;
    std::size_t start = 0;
    while (true) {
      const std::size_t end = text.find(',', start);
      const std::string_view item = std::string_view(text).substr(
          start, end == std::string::npos ? std::string::npos : end - start);
      const std::optional<double> number = parse_number(item);
      if (!number) return text;
      list.push_back(*number);
      if (end == std::string::npos) return list;
      start = end + 1;
    }
  }
  return text;
}

struct GenerateOptions {
  std::string generator;
  std::string out;
  GeneratorRequest request{1.0, 1, ParamSet("--param")};
};

using Table = OptionTable<GenerateOptions>;

void add_param(GenerateOptions& options, const std::string& text) {
  const std::size_t equals = text.find('=');
  if (equals == std::string::npos || equals == 0)
    throw UsageError{"--param: expected key=value, got \"" + text + "\""};
  const std::string key = text.substr(0, equals);
  if (options.request.params.has(key))
    throw UsageError{"--param: " + key + " given more than once"};
  options.request.params.set(key, parse_param_value(text.substr(equals + 1)));
}

const Table& generate_table() {
  static const Table table(
      {"generate", {}, {}, {}},
      {Table::positional("NAME", "the generator (`hapticbench list` names them)", 1, 1,
                         &GenerateOptions::generator)
           .missing("the generator NAME"),
       Table::number("--duration", "S", "the trace's length in seconds",
                     {0, HUGE_VAL, true, false, "a positive number of seconds"},
                     member_of(&GenerateOptions::request, &GeneratorRequest::duration_s))
           .required(),
       Table::whole("--seed", "N", "the seed of the random generators", {},
                    member_of(&GenerateOptions::request, &GeneratorRequest::seed))
           .with_default("1"),
       Table::value("--param", "key=value",
                    "a parameter of the generator (traces/README.md); value: a number, "
                    "comma-separated numbers (e.g. 0,0,0.03), true/false, or a string",
                    add_param)
           .repeatable(),
       Table::value("--out", "FILE.csv",
                    "the trace to write, with its JSON sidecar beside it (FILE.json)",
                    &GenerateOptions::out)
           .required()});
  return table;
}

}  // namespace

int generate_command(const std::vector<std::string>& args) {
  try {
    const GenerateOptions options = generate_table().parse(args);
    if (sidecar_path(options.out) == options.out)
      throw UsageError{"--out: the sidecar is written to <stem>.json, the same name as \"" +
                       options.out + "\"; name the trace FILE.csv"};
    // Never overwrite a trace (or anything else) hapticbench did not generate.
    const auto generated = [&](const std::filesystem::path&) {
      return is_generated_trace(options.out);
    };
    require_replaceable_file(options.out, "generated trace", generated);
    require_replaceable_file(sidecar_path(options.out), "generated trace's sidecar", generated);
    const Trace trace = generate_trace(options.generator, options.request, "generator");
    write_trace_file(options.out, trace);
    std::cout << "wrote " << options.out << " (" << trace.samples.size() << " samples, "
              << trace.info.source << ", seed " << options.request.seed << ")\n";
    return kExitOk;
  } catch (const UsageError& error) {
    return print_usage_error(error, generate_table().usage());
  } catch (const HelpRequested&) {
    return print_help(generate_table().usage());
  } catch (const InputError& error) {
    std::cerr << "error: " << error.what() << "\n";
    return kExitBadInput;
  }
}

const CommandSyntax& generate_syntax() { return generate_table().syntax(); }

}  // namespace hb
