// Cost of one primitive continuous collision query (vertex–face, edge–edge,
// linear motion) over the sample queries of tests/data/, ns per query. Each
// iteration runs the next query of the set, so the time is the mean over
// the set's mix of quick rejections and full bisections. Run:
//   build/tests/bench/ccd_primitives_bench --benchmark_repetitions=5
//       --benchmark_report_aggregates_only=true
#include <benchmark/benchmark.h>

#include <filesystem>
#include <vector>

#include "algorithms/ccd/ccd_primitives.h"
#include "harness/cli/ccd_query_file.h"

namespace hb {
namespace {

const std::filesystem::path kQueryDir =
    std::filesystem::path(HAPTICBENCH_SOURCE_DIR) / "tests/data/ccd-sample-queries";

/// Every query of one kind under kQueryDir (empty when the data is absent);
/// `collisions_only` keeps the queries whose truth is a contact.
std::vector<LinearCcdQuery> load_queries(CcdQueryKind kind, bool collisions_only) {
  std::vector<LinearCcdQuery> queries;
  if (!std::filesystem::is_directory(kQueryDir)) return queries;
  std::vector<std::filesystem::path> paths;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(kQueryDir))
    if (entry.path().extension() == ".csv" && ccd_query_kind_from_path(entry.path()) == kind)
      paths.push_back(entry.path());
  std::sort(paths.begin(), paths.end());
  for (const auto& path : paths)
    for (const LabelledCcdQuery& q : read_ccd_query_file(path).queries)
      if (!collisions_only || q.collides) queries.push_back(q.query);
  return queries;
}

void run_queries(benchmark::State& state, CcdQueryKind kind, bool collisions_only) {
  const std::vector<LinearCcdQuery> queries = load_queries(kind, collisions_only);
  if (queries.empty()) {
    state.SkipWithError(("no query files under " + kQueryDir.string()).c_str());
    return;
  }
  const CcdSettings settings;
  std::size_t next = 0;
  std::int64_t contacts = 0;
  for (auto _ : state) {
    const LinearCcdQuery& query = queries[next];
    const CcdResult result = kind == CcdQueryKind::kVertexFace ? vertex_face_ccd(query, settings)
                                                               : edge_edge_ccd(query, settings);
    benchmark::DoNotOptimize(result);
    contacts += result.contact;
    if (++next == queries.size()) next = 0;
  }
  state.counters["queries_in_set"] = static_cast<double>(queries.size());
  state.counters["contact_share"] =
      static_cast<double>(contacts) / static_cast<double>(state.iterations());
}

void BM_VertexFaceCcd(benchmark::State& state) {
  run_queries(state, CcdQueryKind::kVertexFace, false);
}
void BM_EdgeEdgeCcd(benchmark::State& state) { run_queries(state, CcdQueryKind::kEdgeEdge, false); }
void BM_VertexFaceCcdCollisionsOnly(benchmark::State& state) {
  run_queries(state, CcdQueryKind::kVertexFace, true);
}
void BM_EdgeEdgeCcdCollisionsOnly(benchmark::State& state) {
  run_queries(state, CcdQueryKind::kEdgeEdge, true);
}

BENCHMARK(BM_VertexFaceCcd);
BENCHMARK(BM_EdgeEdgeCcd);
BENCHMARK(BM_VertexFaceCcdCollisionsOnly);
BENCHMARK(BM_EdgeEdgeCcdCollisionsOnly);

}  // namespace
}  // namespace hb

BENCHMARK_MAIN();
