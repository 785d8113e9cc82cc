#include "harness/run/scenario_run_folder.h"

#include "harness/output/run_folder.h"
#include "harness/output/run_report.h"

namespace hb {

bool write_scenario_run_folder(const std::filesystem::path& folder, const ScenarioOutcome& outcome,
                               const std::vector<RunFolderFile>& extra_files, bool sweep_job) {
  StagedRunFolder staged(folder, OutputFolderKind::kRun, /*remove_stale=*/!sweep_job);
  for (std::size_t i = 0; i < outcome.report.runs.size(); ++i) {
    staged.move_file(outcome.report.runs[i].ticks_file, outcome.ticks_files[i]);
    if (!outcome.report.runs[i].schedule_file.empty())
      staged.write_file(outcome.report.runs[i].schedule_file, outcome.schedule_csv[i]);
  }
  staged.write_file("summary.json", summary_json(outcome.report).dump(2) + "\n");
  staged.write_file("junit.xml", junit_xml(outcome.report));
  if (!outcome.intent_csv.empty()) staged.write_file("intent.csv", outcome.intent_csv);
  for (const RunFolderFile& file : extra_files) staged.write_file(file.name, file.content);
  return staged.commit();
}

}  // namespace hb
