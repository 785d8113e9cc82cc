#include "harness/history/history_store.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <map>
#include <set>
#include <tuple>

#include "algorithms/core/replacing_file.h"
#include "hapticbench/input_error.h"
#include "harness/compare/summary_set.h"
#include "harness/process/input_file.h"
#include "harness/scenario/json_fields.h"

namespace hb {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

namespace {

constexpr const char* kIndexName = "history.json";

/// A commit as a folder name's part: letters, digits, '-', '_', '.'.
std::string folder_safe(const std::string& text) {
  std::string out;
  for (char c : text)
    out +=
        std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_' || c == '.' ? c : '_';
  return out.substr(0, 64);
}

Json index_json(const std::vector<HistoryEntry>& entries) {
  Json list = Json::array();
  for (const HistoryEntry& entry : entries)
    list.push_back({{"commit", entry.commit},
                    {"date", entry.date},
                    {"folder", entry.folder},
                    {"scenarios", entry.scenarios}});
  return {{"schema_version", 1}, {"entries", list}};
}

/// The folder an entry is written in before it takes its name.
fs::path staging_path(const fs::path& history_dir, const std::string& folder) {
  return history_dir / (".staging-" + folder + "-" + std::to_string(::getpid()));
}

}  // namespace

std::vector<HistoryEntry> read_history(const fs::path& history_dir) {
  std::error_code error;
  if (!fs::exists(history_dir, error)) return {};
  if (!fs::is_directory(history_dir, error))
    throw InputError(history_dir.string(), "", "expected a history folder, found a file");
  const fs::path index = history_dir / kIndexName;
  if (!fs::exists(index, error)) {
    if (fs::directory_iterator(history_dir, error) != fs::directory_iterator())
      throw InputError(history_dir.string(), "",
                       "holds files but no history.json: not a history folder (give a new or "
                       "empty folder, or one that `hapticbench history add` wrote)");
    return {};
  }
  const std::string source = index.string();
  const Json document = parse_json_document(read_regular_file(index, "history.json"), source);
  const JsonField root(document, source, "");
  root.require_object("expected {\"schema_version\": 1, \"entries\": [...]}");
  if (root.member("schema_version", "1").integer(1, 1, "expected 1") != 1) return {};
  const JsonField list = root.member("entries", "the entries, oldest first");
  std::vector<HistoryEntry> entries;
  const std::size_t count = list.array_size("expected an array of entries");
  for (std::size_t i = 0; i < count; ++i) {
    const JsonField item = list.element(i);
    item.require_object("expected {\"commit\", \"date\", \"folder\", \"scenarios\"}");
    HistoryEntry entry;
    entry.commit = item.member("commit", "the commit").string("expected a string");
    entry.date = item.member("date", "the date").string("expected a string");
    entry.folder = item.member("folder", "the entry's folder").string("expected a string");
    if (entry.folder.empty() || entry.folder != folder_safe(entry.folder) || entry.folder[0] == '.')
      item.existing_member("folder").fail("expected a folder name inside the history folder");
    const JsonField names = item.member("scenarios", "the scenario names");
    const std::size_t scenario_count = names.array_size("expected an array of names");
    for (std::size_t s = 0; s < scenario_count; ++s)
      entry.scenarios.push_back(names.element(s).string("expected a scenario name"));
    entries.push_back(std::move(entry));
  }
  return entries;
}

HistoryEntry add_to_history(const fs::path& history_dir, const std::vector<fs::path>& run_dirs,
                            const std::optional<std::string>& commit) {
  std::vector<HistoryEntry> entries = read_history(history_dir);  // refuses a foreign folder

  // Every summary first: nothing is written unless all of them read.
  struct Stored {
    std::string scenario;
    std::string bytes;
    std::string date;
  };
  std::vector<Stored> stored;
  std::set<std::string> commits;
  for (const fs::path& run_dir : run_dirs) {
    const SummarySet set = load_summary_set(run_dir);
    for (const ScenarioSummary& summary : set.scenarios) {
      Stored item{summary.scenario_name, read_regular_file(summary.source, "a summary.json"), ""};
      const Json parsed = parse_json_document(item.bytes, summary.source);
      const Json::json_pointer date("/context/date");
      if (parsed.contains(date) && parsed[date].is_string()) item.date = parsed[date];
      for (const Stored& earlier : stored)
        if (earlier.scenario == item.scenario)
          throw InputError(summary.source, "/scenario/name",
                           "scenario \"" + item.scenario +
                               "\" is given twice; an entry holds each scenario once");
      commits.insert(summary.context.commit);
      stored.push_back(std::move(item));
    }
  }
  if (!commit && commits.size() != 1) {
    std::string named;
    for (const std::string& c : commits) named += (named.empty() ? "" : ", ") + c;
    throw InputError("", "--commit",
                     "the runs name different commits (" + named +
                         "): say which commit they stand for with --commit ID");
  }

  HistoryEntry entry;
  entry.commit = commit.value_or(*commits.begin());
  for (const Stored& item : stored) {
    entry.scenarios.push_back(item.scenario);
    entry.date = std::max(entry.date, item.date);
  }
  std::sort(entry.scenarios.begin(), entry.scenarios.end());
  auto same = std::find_if(entries.begin(), entries.end(),
                           [&](const HistoryEntry& e) { return e.commit == entry.commit; });
  char number[16];
  std::snprintf(number, sizeof number, "%04zu",
                same != entries.end() ? static_cast<std::size_t>(same - entries.begin()) + 1
                                      : entries.size() + 1);
  entry.folder = std::string(number) + "-" + folder_safe(entry.commit);

  // A folder of that name that history.json does not list is not ours.
  std::error_code error;
  if (same == entries.end() && fs::exists(history_dir / entry.folder, error))
    throw InputError((history_dir / entry.folder).string(), "",
                     "is in the history folder but history.json does not list it; nothing "
                     "was written (move it away)");
  // The entry's folder, written whole under a staging name, then swapped in.
  fs::create_directories(history_dir);
  const fs::path staging = staging_path(history_dir, entry.folder);
  fs::remove_all(staging);
  for (const Stored& item : stored) {
    fs::create_directories(staging / item.scenario);
    write_file_replacing(staging / item.scenario / "summary.json", item.bytes);
  }
  const fs::path destination = history_dir / entry.folder;
  const fs::path old = staging.string() + ".old";
  if (same != entries.end()) {
    if (fs::exists(history_dir / same->folder)) fs::rename(history_dir / same->folder, old);
    *same = entry;
  } else {
    entries.push_back(entry);
  }
  fs::rename(staging, destination);
  write_file_replacing(history_dir / kIndexName, index_json(entries).dump(2) + "\n");
  fs::remove_all(old);
  return entry;
}

std::vector<HistoryMove> first_moves(const fs::path& history_dir,
                                     const std::vector<HistoryEntry>& entries,
                                     const CompareOptions& options) {
  std::vector<HistoryMove> moves;
  std::set<std::tuple<std::string, std::string, std::string>> seen;
  for (std::size_t i = 1; i < entries.size(); ++i) {
    const SummarySet before = load_summary_set(history_dir / entries[i - 1].folder);
    const SummarySet after = load_summary_set(history_dir / entries[i].folder);
    const Comparison comparison = compare_summary_sets(before, after, options);
    for (const CheckRow& row : comparison.rows) {
      const bool moved = is_failing(row.verdict) || row.verdict == Verdict::kImproved;
      if (moved && seen.insert({row.scenario, row.label, row.check}).second)
        moves.push_back({i, row});
    }
  }
  return moves;
}

}  // namespace hb
