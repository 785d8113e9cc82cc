// Contact discovery for a haptic-rate constraint solve, shared by the
// god-object's haptic proxy and the constrained-dynamics proxy: the slow
// loop's proximity query around an anchor pose (a certificate listing every
// feature pair within a band), how wide the band should be, whether a pose
// is still within the certificate's reach, and a listed pair's closest
// points re-evaluated at the current pose (why a proxy that stays within
// reach cannot pass a pair that is not listed: docs/algorithms/god-object.md).
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "algorithms/ccd/mesh_ccd.h"
#include "algorithms/contact/contact_settings.h"
#include "algorithms/contact/proxy_motion.h"
#include "hapticbench/pose.h"

namespace hb {

/// Pairs a proximity query lists first (ProximityCertifier::certify).
inline constexpr std::size_t kFirstListedPairs = 256;
/// How much farther than the band a tree search looks (a fraction of the
/// band), so that its pairs answer the next queries while the tool moves.
inline constexpr double kSearchMargin = 0.5;
/// How many pairs a tree search keeps per pair the query lists (at most
/// settings.haptic_max_pairs), so that a list cut short by its limit can be
/// answered again from them.
inline constexpr std::size_t kSearchedPairsPerListed = 2;
/// How far (in widest bands, ContactSettings::haptic_band_m) a search that
/// found nothing near measures the scene's distance: the certificate's
/// clearance, and so the proxy's reach, in free space.
inline constexpr double kFreeSpaceReachBands = 10;
/// Searches that ask only for what they need before a wider one is tried
/// again, after the wider ones were not used (ProximityCertifier::certify).
inline constexpr int kPlainSearchesBetweenTries = 8;

/// A search ahead (ProximityCertifier::certify) starts when the kept
/// search's pairs can answer at most this many more queries at the tool's
/// motion per query, and at least kAheadLeastQueries (fewer leave no time
/// to share its work).
inline constexpr double kAheadLeadQueries = 12;
inline constexpr double kAheadLeastQueries = 2;
/// It looks this many bands beyond the band and keeps up to this many pairs
/// per pair listed (within settings.haptic_max_pairs; more pairs buy room
/// cheaply: docs/algorithms/god-object.md).
inline constexpr double kAheadMargin = 1.5;
inline constexpr std::size_t kAheadPairsPerListed = 8;
/// The most node pairs a query opens of it (about 0.3 ms on a crowded
/// contact), and the least.
inline constexpr int64_t kAheadSliceNodePairs = 300;
inline constexpr int64_t kAheadLeastSlice = 64;
/// Node pairs the free-space measurement opens (kFreeSpaceReachBands): its
/// best-first search's least open bound by then is the clearance.
inline constexpr int64_t kFreeSpaceNodePairs = 1024;

/// What a proximity query certifies around an anchor pose: within reach
/// clearance_m − standoff of the anchor (point_reach of the displacement
/// from it), only the listed pairs can come closer than the standoff.
struct ProximityCertificate {
  Pose anchor;  ///< the tool's centre-of-mass frame (world) the pairs were found at
  std::vector<ContactFeatures> pairs;  ///< every pair closer than clearance_m at the anchor
  std::vector<double> distances;       ///< per pair, its distance at the anchor (m), ascending
  double clearance_m = 0;              ///< every other pair is at least this far apart there
  /// Tree searches the certificate took: 0 when the pairs of an earlier
  /// search answered it (ProximityCertifier::certify), else 1 or 2.
  int searches = 0;
  /// Searches ahead (worked in slices over the queries before) that the
  /// query took as its pairs' source when they were complete.
  int ahead_searches = 0;
  /// Listed pairs that repeat an earlier listed one: the same kind and tool
  /// feature, scene features at one place (MeshCcd::scene_feature_place:
  /// tiles that share a corner), so the same closest points at every pose.
  /// Both empty when no pair repeats another. Otherwise `first_of_kind`
  /// holds the listed index of each pair that repeats none, ascending, and
  /// `measured_as` per listed pair the position in it of the pair it
  /// repeats (its own when it repeats none).
  std::vector<int> first_of_kind;
  std::vector<int> measured_as;
};

/// How many of the certificate's pairs are at most `distance_m` apart at
/// its anchor: a prefix of the list, whose distances ascend (all of them
/// when the certificate has no distances).
std::size_t pairs_within(const ProximityCertificate& certificate, double distance_m);

/// A listed pair at one pose.
struct PairContact {
  Vec3 scene_point = Vec3::Zero();  ///< world, m: the scene feature's closest point
  Vec3 tool_point = Vec3::Zero();   ///< world, m: the tool feature's closest point
  /// World, unit, pushes the tool out of the scene: from the scene point to
  /// the tool point (the pair's own normal when they coincide).
  Vec3 normal = Vec3::UnitZ();
  double distance = 0;  ///< m, between the two features (≥ 0)
};

/// Per-pair impulses (`impulses`, one per pair of `from`) carried over to
/// the pairs of `to`, by feature pair; zero where `to` lists a pair `from`
/// did not carry an impulse for. Only pairs with an impulse are looked up
/// (a few, near the front of `to`, which lists the nearest first).
void carry_impulses(std::span<const ContactFeatures> from, std::span<const Vec3> impulses,
                    std::span<const ContactFeatures> to, std::vector<Vec3>& carried);

/// The slow loop's proximity query and the haptic loop's re-evaluation of
/// its pairs. The certifier itself does not change after construction;
/// what changes lives in workspaces its callers own and pass in: a
/// QueryWorkspace per sequence of queries (certify), an
/// EvaluationWorkspace per thread that evaluates. Calls with different
/// workspaces may run at the same time.
class ProximityCertifier {
 public:
  /// What one sequence of queries (certify) keeps from query to query — the
  /// last tree search's pairs, the search ahead, how the next query lists
  /// and searches — and the scratch a query reuses. Owned by the thread
  /// that queries (the slow loop); a query with it allocates only while
  /// the pairs it keeps grow.
  class QueryWorkspace {
   public:
    /// Forgets the kept search and what the last queries decided, so that a
    /// run from reset() answers as the first did (a free-space answer from
    /// kept pairs is the search's clearance less the motion since, not what
    /// a new search would measure).
    void forget();

   private:
    friend class ProximityCertifier;

    /// The pairs of the last tree search: every pair within clearance_m of
    /// the tool at `anchor` (centre-of-mass frame, world) is among them.
    struct SearchedPairs {
      Pose anchor;
      std::vector<ProximityPair> pairs;  ///< with their distances at `anchor`
      double clearance_m = -1;           ///< m; < 0 before the first search
      bool widened = false;              ///< it looked kSearchMargin farther than asked
      /// Per pair, its group: the pairs of one kind and tool feature whose
      /// scene features share a place (MeshCcd::scene_feature_places),
      /// which have the same closest points at every pose. Empty when no
      /// scene features share a place.
      std::vector<int> group;
    };

    /// A search started ahead of need, worked in slices by the queries.
    struct SearchAhead {
      ProximityInSlices search;
      Pose anchor;  ///< centre-of-mass frame (world) it searches at
    };

    /// The last query found more pairs crowding the standoff than it lists
    /// first: the next lists the most at once (a hint between queries; a
    /// certificate is valid whichever way it was listed).
    bool crowded_ = false;
    SearchedPairs searched_;
    std::optional<SearchAhead> ahead_;
    /// Node pairs the last complete search opened: what the next is
    /// expected to open.
    int64_t search_node_pairs_ = 0;
    /// The last query's anchor and its certificate's clearance (m).
    std::optional<Pose> last_anchor_;
    double last_clearance_m_ = 0;
    /// Whether searches look wider than asked (certify decides), the plain
    /// searches since the last wider one, and whether the last certificate
    /// ended with a wider search.
    bool widen_ = true;
    int plain_searches_ = 0;
    bool last_search_widened_ = false;
    /// Per pair of the last listed_pairs answer, its group (SearchedPairs);
    /// empty without groups.
    std::vector<int> listed_groups_;

    /// Scratch of the re-measurement (answer_from_searched): the searched
    /// pairs that may be within reach, their closest points at the query's
    /// pose, and the nearest of those within it (by distance, order_).
    std::vector<ContactFeatures> to_measure_;
    std::vector<PairClosestPoints> measured_points_;
    std::vector<ProximityPair> measured_;
    std::vector<std::pair<double, int>> order_;
    /// Scratch of the grouping: per group, −1 between uses.
    std::vector<int> group_first_, group_slot_;
    std::vector<ContactFeatures> features_, firsts_measured_;
    std::vector<int> places_, measured_index_;
  };

  /// Scratch of evaluate(pairs) and evaluate_listed. Owned by the thread
  /// that evaluates (the haptic loop), reused from tick to tick.
  class EvaluationWorkspace {
   private:
    friend class ProximityCertifier;
    std::vector<PairClosestPoints> points_;
    std::vector<ContactFeatures> firsts_;  ///< evaluate_listed's pairs that repeat none
  };

  /// `ccd` must outlive the certifier. Settings as read by
  /// read_contact_settings; centre_of_mass in tool coordinates (m).
  ProximityCertifier(const MeshCcd& ccd, const ContactSettings& settings,
                     const Vec3& centre_of_mass);

  /// The proximity query at `tool_pose`, listing pairs within `band_m`
  /// (m): the kFirstListedPairs nearest, or, when those leave a reach below
  /// a third of the band, up to settings.haptic_max_pairs nearest. Answered
  /// from the pairs `queries` kept when they hold the answer, else by a
  /// tree search (docs/algorithms/god-object.md); the answer is the same.
  ProximityCertificate certify(QueryWorkspace& queries, const Pose& tool_pose, double band_m) const;

  /// The band (m) for the next certificate: six times how far
  /// (point_reach) the device moved from `previous_target` to `target`
  /// between two slow updates, within the settings' [haptic_band_min_m,
  /// haptic_band_m].
  double band_for(const Pose& previous_target, const Pose& target) const;
  double widest_band() const { return settings_.haptic_band_m; }  ///< m

  /// How far (point_reach, m) the proxy may move from the certificate's anchor.
  double reach(const ProximityCertificate& certificate) const {
    return certificate.clearance_m - settings_.standoff_m;
  }
  /// Whether the tool-frame pose lies within the certificate's reach.
  bool within_reach(const ProximityCertificate& certificate, const Pose& tool_pose) const;

  /// The pair at the tool's centre-of-mass frame `com_pose` (world).
  PairContact evaluate(const ContactFeatures& pair, const Pose& com_pose) const;
  /// evaluate(pairs[k], com_pose) for every k, in `contacts` (resized): the
  /// same values, the tool's rotation worked out once.
  void evaluate(EvaluationWorkspace& workspace, std::span<const ContactFeatures> pairs,
                const Pose& com_pose, std::vector<PairContact>& contacts) const;

  /// evaluate of the certificate's first `count` listed pairs: the same
  /// values, each pair that repeats an earlier one (measured_as) taking
  /// that one's closest points instead of measuring them again.
  void evaluate_listed(EvaluationWorkspace& workspace, const ProximityCertificate& certificate,
                       std::size_t count, const Pose& com_pose,
                       std::vector<PairContact>& contacts) const;

  const ProxyFrames& frames() const { return frames_; }
  /// The tool's radius about its centre of mass (m; 0 for a point tool).
  double radius() const { return radius_; }

 private:
  using SearchedPairs = QueryWorkspace::SearchedPairs;
  using SearchAhead = QueryWorkspace::SearchAhead;

  /// Completes `search`, started at `anchor` (looking kSearchMargin or
  /// kAheadMargin farther than asked when `widened`), and keeps it: in free
  /// space with the scene's distance as its clearance (kFreeSpaceReachBands).
  void keep_search(QueryWorkspace& queries, const Pose& anchor, ProximityInSlices search,
                   bool widened) const;
  /// How many pairs a search keeps for a query listing max_pairs when it
  /// keeps per_listed per listed pair (within settings.haptic_max_pairs).
  std::size_t pairs_kept(std::size_t max_pairs, std::size_t per_listed) const;
  /// How many more queries at the tool's motion since the last query (from
  /// it to `anchor`) the kept search's pairs can answer; infinite for a
  /// tool at rest.
  double queries_left(const QueryWorkspace& queries, const Pose& anchor) const;
  /// Works the search ahead by this query's share (the rest of its expected
  /// node pairs over the queries left), keeping it when complete; whether
  /// it was kept.
  bool advance_search_ahead(QueryWorkspace& queries, const Pose& anchor) const;
  /// Completes the search ahead and keeps it, if there is one; whether there was.
  bool complete_search_ahead(QueryWorkspace& queries) const;
  /// Starts a search ahead when none runs and the queries left are between
  /// kAheadLeastQueries and kAheadLeadQueries.
  void start_search_ahead(QueryWorkspace& queries, const ProximityCertificate& certificate,
                          double band_m, std::size_t max_pairs) const;

  /// The max_pairs nearest pairs within band_m at `anchor` and their
  /// clearance (MeshCcd::proximity's answer), from the last search's pairs
  /// when they hold the answer, else from the search ahead completed here
  /// (counted in `ahead_searches`) when its pairs hold it, else from a new
  /// search (counted in `searches`).
  ProximityResult listed_pairs(QueryWorkspace& queries, const Pose& anchor, double band_m,
                               std::size_t max_pairs, int& searches, int& ahead_searches) const;
  /// The pair as `points` (its closest points at com_pose) give it.
  PairContact contact_of(const ContactFeatures& pair, const PairClosestPoints& points,
                         const Pose& com_pose) const;
  /// The answer from the searched pairs at `anchor`, if they hold it.
  std::optional<ProximityResult> answer_from_searched(QueryWorkspace& queries, const Pose& anchor,
                                                      double band_m, std::size_t max_pairs) const;
  /// Marks the certificate's repeated pairs (first_of_kind, measured_as)
  /// from the listed pairs' groups.
  void mark_repeats(QueryWorkspace& queries, ProximityCertificate& certificate) const;
  /// The groups of the pairs of a new search (SearchedPairs::group).
  void group_searched_pairs(QueryWorkspace& queries) const;
  /// answer_from_searched's re-measurement with groups: the searched pairs
  /// whose distance less `moved` is within `reachable`, measured at
  /// `anchor` once per group; the `needed` nearest of those within `within`
  /// in the workspace's measured pairs by distance, with their groups.
  void measure_grouped(QueryWorkspace& queries, const Pose& anchor, double moved, double reachable,
                       double within, std::size_t needed) const;

  const MeshCcd& ccd_;
  ContactSettings settings_;
  ProxyFrames frames_;
  double radius_;
};

}  // namespace hb
