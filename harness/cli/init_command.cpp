// hapticbench init FILE.json [--scene SHAPE|MESH] [--tool SHAPE|MESH]
// A scenario to start from: a scene object with its top face at z = 0, a
// tool, a press aimed at the scene's top, the algorithms that can render
// that pair, a reference and budgets, each section explained in comments
// (init_scenario.h).
#include <filesystem>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include "algorithms/core/replacing_file.h"
#include "hapticbench/input_error.h"
#include "harness/cli/command_line.h"
#include "harness/cli/commands.h"
#include "harness/cli/init_scenario.h"
#include "harness/cli/option_table.h"
#include "harness/sweep/job_name.h"

namespace hb {

namespace fs = std::filesystem;

namespace {

struct InitArguments {
  std::string file;
  std::string scene = "box", tool = "sphere";
};

using Table = OptionTable<InitArguments>;

const Table& init_table() {
  static const Table table(
      {"init",
       {"Writes a scenario to start from, explained in // comments: the scene object's top at "
        "z = 0, the tool above it, a press into it, the algorithms that render the pair, the "
        "reference and budgets. Never overwrites a file."},
       {},
       {}},
      {Table::positional("FILE.json", "the scenario file to write; its name names the scenario", 1,
                         1, &InitArguments::file),
       Table::value("--scene", "SHAPE|MESH",
                    "box, sphere, capsule, box_with_hole, or a mesh file (.off/.obj/.stl/.ply, "
                    "in metres: set \"scale\" otherwise)",
                    &InitArguments::scene)
           .with_default("box"),
       Table::value("--tool", "SHAPE|MESH", "sphere, box, capsule, or a mesh file",
                    &InitArguments::tool)
           .with_default("sphere")});
  return table;
}

InitArguments parse_init_arguments(const std::vector<std::string>& args) {
  InitArguments parsed = init_table().parse(args);
  if (fs::path(parsed.file).extension() != ".json")
    throw UsageError{"the scenario file's name ends in .json, got \"" + parsed.file + "\""};
  return parsed;
}

}  // namespace

int init_command(const std::vector<std::string>& args) {
  int exit_code = 0;
  const std::optional<InitArguments> parsed = parse_command_line(
      [&] { return parse_init_arguments(args); }, init_table().usage(), exit_code);
  if (!parsed) return exit_code;
  const fs::path file(parsed->file);
  const std::string name = file.stem().string();
  if (!is_safe_folder_name(name))
    throw InputError(parsed->file, "",
                     "the file's name (without .json) names the scenario and its run folder: "
                     "letters, digits, '_', '.', '-', '='");
  std::error_code error;
  if (fs::exists(fs::symlink_status(file, error)))
    throw InputError(parsed->file, "", "exists already; init never overwrites a file");
  const fs::path folder = file.parent_path().empty() ? fs::path(".") : file.parent_path();
  const InitPart scene = is_mesh_path(parsed->scene)
                             ? init_mesh_part(parsed->scene, folder, false)
                             : init_primitive(parsed->scene, /*tool=*/false);
  const InitPart tool = is_mesh_path(parsed->tool) ? init_mesh_part(parsed->tool, folder, true)
                                                   : init_primitive(parsed->tool, /*tool=*/true);
  const std::string scene_name =
      scene.mesh ? fs::path(parsed->scene).filename().string() : parsed->scene;
  const std::string tool_name =
      tool.mesh ? fs::path(parsed->tool).filename().string() : parsed->tool;
  TemporarySibling written(file);
  written.write(init_scenario_text(name, scene, tool, scene_name, tool_name));
  written.commit();
  std::cout << "wrote " << parsed->file << ": a " << tool_name << " pressed into a " << scene_name
            << "; next: hapticbench validate " << parsed->file << "\n";
  return kExitOk;
}

const CommandSyntax& init_syntax() { return init_table().syntax(); }

}  // namespace hb
