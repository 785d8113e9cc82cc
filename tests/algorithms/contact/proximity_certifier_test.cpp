// Certificates over tiles laid edge to edge, whose pairs repeat one another
// (a tool vertex over the corner four tiles share): each repeated pair is
// measured once for all, and every value is what measuring each pair gives.
#include "algorithms/contact/proximity_certifier.h"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <vector>

#include "tests/support/proxy_fixtures.h"

namespace hb {
namespace {

bool same_contact(const PairContact& a, const PairContact& b) {
  return a.scene_point == b.scene_point && a.tool_point == b.tool_point && a.normal == b.normal &&
         a.distance == b.distance;
}

}  // namespace

TEST_CASE("a certificate over tiles edge to edge measures each repeated pair once, exactly") {
  // A 5 cm box over 6 × 6 tiles of 1 cm, 0.3 mm above them and tilted a
  // little, sliding and turning in small steps: the first certificate
  // searches, most later ones measure the searched pairs again.
  const std::vector<SceneObject> scene = test::box_tiles(6, 0.01, 0.0);
  const Tool tool = test::meshed_box_tool(Vec3(0.05, 0.05, 0.02));
  const MeshCcd ccd(tool.mesh, scene);
  REQUIRE(ccd.scene_features_share_places());
  ContactSettings settings;
  const ProximityCertifier certifier(ccd, settings, Vec3::Zero());
  ProximityCertifier::QueryWorkspace queries;
  ProximityCertifier::EvaluationWorkspace evaluation;
  int remeasured = 0, with_repeats = 0;
  for (int step = 0; step < 40; ++step) {
    const double t = step / 40.0;
    const Quat q(Eigen::AngleAxisd(0.05 * t, Vec3::UnitZ()) *
                 Eigen::AngleAxisd(0.002, Vec3(1, 0.5, 0).normalized()));
    const Pose pose{Vec3(0.03 + 0.002 * t, 0.03 + 0.001 * t, 0.0103 - 0.0002 * t), q};
    const ProximityCertificate certificate = certifier.certify(queries, pose, 0.002);
    const std::vector<ContactFeatures>& pairs = certificate.pairs;
    INFO("step " << step << ", " << pairs.size() << " pairs, " << certificate.searches
                 << " searches");
    REQUIRE(!pairs.empty());
    if (!certificate.measured_as.empty()) {
      ++with_repeats;
      REQUIRE(certificate.measured_as.size() == pairs.size());
      const std::vector<int>& firsts = certificate.first_of_kind;
      CHECK(std::is_sorted(firsts.begin(), firsts.end()));
      CHECK(firsts.size() < pairs.size());
      for (std::size_t k = 0; k < pairs.size(); ++k) {
        const auto first =
            static_cast<std::size_t>(firsts[static_cast<std::size_t>(certificate.measured_as[k])]);
        REQUIRE(first <= k);
        CHECK(pairs[first].kind == pairs[k].kind);
        CHECK(pairs[first].tool_feature == pairs[k].tool_feature);
        CHECK(certificate.distances[first] == certificate.distances[k]);
      }
    }
    // Answered from the searched pairs, every distance is the pair's own
    // measurement at the anchor, bit for bit.
    if (certificate.searches == 0) {
      ++remeasured;
      for (std::size_t k = 0; k < pairs.size(); ++k)
        CHECK(certificate.distances[k] ==
              ccd.closest_points(pairs[k], certificate.anchor).distance);
    }
    // Evaluated with the repeats measured once: each pair's own contact.
    Vec6 moved;
    moved << 1e-5, -2e-5, -1e-5, 1e-4, -2e-4, 3e-4;
    const Pose there = displaced(certificate.anchor, moved);
    for (const std::size_t count : {pairs.size(), pairs.size() / 2}) {
      std::vector<PairContact> listed, each;
      certifier.evaluate_listed(evaluation, certificate, count, there, listed);
      certifier.evaluate(evaluation, std::span<const ContactFeatures>(pairs).first(count), there,
                         each);
      REQUIRE(listed.size() == count);
      for (std::size_t k = 0; k < count; ++k) CHECK(same_contact(listed[k], each[k]));
    }
  }
  CHECK(remeasured > 20);
  CHECK(with_repeats > 20);
}

TEST_CASE("searches ahead, worked a slice a query, answer as a new search would") {
  // A 5 cm box sliding steadily 0.3 mm over 1 cm tiles 0.05 mm apart, 20 um
  // a query and turning a little: the pairs it keeps run out every few
  // queries, so searches start ahead of need and are taken when complete.
  // Each certificate is compared with a search of its own at its pose; the
  // tiles' shared corners put many pairs at one distance.
  const std::vector<SceneObject> scene = test::box_tiles(8, 0.01, 5e-5);
  const Tool tool = test::meshed_box_tool(Vec3(0.05, 0.05, 0.02));
  const MeshCcd ccd(tool.mesh, scene);
  const ContactSettings settings;
  const ProximityCertifier certifier(ccd, settings, Vec3::Zero());
  ProximityCertifier::QueryWorkspace workspace;
  const double band = 0.0006;
  int searches = 0, ahead = 0, queries = 0;
  for (int step = 0; step < 400; ++step) {
    const Quat q(Eigen::AngleAxisd(2e-4 * step, Vec3::UnitZ()));
    const Pose pose{Vec3(0.03 + 2e-5 * step, 0.03 + 1e-5 * step, 0.0103), q};
    const ProximityCertificate certificate = certifier.certify(workspace, pose, band);
    searches += certificate.searches;
    ahead += certificate.ahead_searches;
    ++queries;
    const std::size_t limit = certificate.pairs.size() > kFirstListedPairs
                                  ? static_cast<std::size_t>(settings.haptic_max_pairs)
                                  : kFirstListedPairs;
    const ProximityResult searched = ccd.proximity(certificate.anchor, band, limit);
    INFO("query " << step << ": " << certificate.pairs.size() << " pairs, searches "
                  << certificate.searches << ", ahead " << certificate.ahead_searches);
    // The same list in the same order (pairs at one distance by their
    // features), whichever search the pairs came from.
    REQUIRE(certificate.pairs.size() == searched.pairs.size());
    CHECK(certificate.clearance_m == Approx(searched.clearance_m).margin(1e-12));
    for (std::size_t k = 0; k < searched.pairs.size(); ++k) {
      CHECK(certificate.pairs[k] == searched.pairs[k].features);
      CHECK(certificate.distances[k] == Approx(searched.pairs[k].distance).margin(1e-15));
    }
  }
  INFO(searches << " searches and " << ahead << " searches ahead for " << queries << " queries");
  CHECK(ahead >= 5);
  CHECK(searches * 10 < queries);
  // Forgotten, the next query searches as the first did.
  workspace.forget();
  const ProximityCertificate first =
      certifier.certify(workspace, Pose{Vec3(0.03, 0.03, 0.0103), Quat::Identity()}, band);
  CHECK(first.searches == 1);
  CHECK(first.ahead_searches == 0);
}

TEST_CASE("a scene whose features are all apart lists no repeats") {
  const std::vector<SceneObject> scene = test::box_tiles(3, 0.01, 2e-4);
  const Tool tool = test::meshed_box_tool(Vec3(0.03, 0.03, 0.02));
  const MeshCcd ccd(tool.mesh, scene);
  const ProximityCertifier certifier(ccd, ContactSettings{}, Vec3::Zero());
  ProximityCertifier::QueryWorkspace queries;
  const ProximityCertificate certificate =
      certifier.certify(queries, Pose{Vec3(0.01, 0.01, 0.0102), Quat::Identity()}, 0.002);
  REQUIRE(!certificate.pairs.empty());
  CHECK(certificate.first_of_kind.empty());
  CHECK(certificate.measured_as.empty());
}

TEST_CASE("one certifier answers two query workspaces as two certifiers would") {
  // Two boxes' worth of queries, one sliding and one sinking over the same
  // tiles, alternate on one certifier, each with its own workspace: each
  // sequence gets what a certifier of its own gives it, bit for bit.
  const std::vector<SceneObject> scene = test::box_tiles(6, 0.01, 0.0);
  const Tool tool = test::meshed_box_tool(Vec3(0.05, 0.05, 0.02));
  const MeshCcd ccd(tool.mesh, scene);
  const ContactSettings settings;
  const ProximityCertifier shared(ccd, settings, Vec3::Zero());
  const ProximityCertifier own_sliding(ccd, settings, Vec3::Zero());
  const ProximityCertifier own_sinking(ccd, settings, Vec3::Zero());
  ProximityCertifier::QueryWorkspace sliding, sinking, alone_sliding, alone_sinking;
  const auto same = [](const ProximityCertificate& a, const ProximityCertificate& b) {
    return a.pairs == b.pairs && a.distances == b.distances && a.clearance_m == b.clearance_m &&
           a.searches == b.searches && a.ahead_searches == b.ahead_searches &&
           a.measured_as == b.measured_as;
  };
  for (int step = 0; step < 30; ++step) {
    const Pose slide{Vec3(0.03 + 4e-5 * step, 0.03, 0.0103), Quat::Identity()};
    const Pose sink{Vec3(0.025, 0.028, 0.0112 - 4e-5 * step), Quat::Identity()};
    INFO("step " << step);
    CHECK(same(shared.certify(sliding, slide, 0.002),
               own_sliding.certify(alone_sliding, slide, 0.002)));
    CHECK(same(shared.certify(sinking, sink, 0.002),
               own_sinking.certify(alone_sinking, sink, 0.002)));
  }
}

}  // namespace hb
