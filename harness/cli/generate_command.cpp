// `hapticbench generate`: runs a synthetic trace generator and writes the
// trace as hapticbench CSV with its JSON sidecar.
#include <charconv>
#include <cstdint>
#include <exception>
#include <filesystem>
#include <iostream>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include "hapticbench/input_error.h"
#include "hapticbench/param_set.h"
#include "harness/cli/command_line.h"
#include "harness/cli/commands.h"
#include "harness/output/output_ownership.h"
#include "harness/trace/generators.h"
#include "harness/trace/trace.h"

namespace hb {

namespace {

constexpr const char* kGenerateUsage =
    "usage: hapticbench generate NAME --duration S [--seed N] [--param key=value]... --out "
    "FILE.csv\n"
    "  value: a number, comma-separated numbers (e.g. 0,0,0.03), true/false, or a string\n";

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
  bool has_duration = false;
};

GenerateOptions parse_generate_options(const std::vector<std::string>& args) {
  GenerateOptions options;
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& arg = args[i];
    check_help(arg);
    auto value = [&]() -> const std::string& { return option_value(args, i); };
    if (arg == "--duration") {
      const std::string& text = value();
      const std::optional<double> duration = parse_number(text);
      if (!duration || !(*duration > 0))
        throw UsageError{"--duration: expected a positive number of seconds, got \"" + text + "\""};
      options.request.duration_s = *duration;
      options.has_duration = true;
    } else if (arg == "--seed") {
      const std::string& text = value();
      const std::optional<long long> seed =
          parse_whole_number(text, 0, std::numeric_limits<long long>::max());
      if (!seed) throw UsageError{"--seed: expected a whole number >= 0, got \"" + text + "\""};
      options.request.seed = static_cast<uint64_t>(*seed);
    } else if (arg == "--param") {
      const std::string& text = value();
      const std::size_t equals = text.find('=');
      if (equals == std::string::npos || equals == 0)
        throw UsageError{"--param: expected key=value, got \"" + text + "\""};
      const std::string key = text.substr(0, equals);
      if (options.request.params.has(key))
        throw UsageError{"--param: " + key + " given more than once"};
      options.request.params.set(key, parse_param_value(text.substr(equals + 1)));
    } else if (arg == "--out") {
      options.out = value();
    } else if (arg.rfind("--", 0) == 0) {
      throw UsageError{"unknown option " + arg};
    } else if (options.generator.empty()) {
      options.generator = arg;
    } else {
      throw UsageError{"unexpected argument \"" + arg + "\" (the generator is \"" +
                       options.generator + "\")"};
    }
  }
  if (options.generator.empty()) throw UsageError{"missing the generator NAME"};
  if (!options.has_duration) throw UsageError{"missing --duration S"};
  if (options.out.empty()) throw UsageError{"missing --out FILE.csv"};
  return options;
}

}  // namespace

int generate_command(const std::vector<std::string>& args) {
  try {
    const GenerateOptions options = parse_generate_options(args);
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
    return print_usage_error(error, kGenerateUsage);
  } catch (const HelpRequested&) {
    return print_help(kGenerateUsage);
  } catch (const InputError& error) {
    std::cerr << "error: " << error.what() << "\n";
    return kExitBadInput;
  }
}

}  // namespace hb
