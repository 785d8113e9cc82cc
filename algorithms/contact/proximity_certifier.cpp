#include "algorithms/contact/proximity_certifier.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <utility>

namespace hb {

namespace {
// Below this distance (m) a pair's closest points give no direction; the
// pair's own normal is used instead.
constexpr double kDirectionFloor = 1e-12;
}  // namespace

std::size_t pairs_within(const ProximityCertificate& certificate, double distance_m) {
  const std::vector<double>& distances = certificate.distances;
  if (distances.size() != certificate.pairs.size()) return certificate.pairs.size();
  return static_cast<std::size_t>(std::upper_bound(distances.begin(), distances.end(), distance_m) -
                                  distances.begin());
}

void carry_impulses(std::span<const ContactFeatures> from, std::span<const Vec3> impulses,
                    std::span<const ContactFeatures> to, std::vector<Vec3>& carried) {
  carried.assign(to.size(), Vec3::Zero());
  for (std::size_t old = 0; old < impulses.size() && old < from.size(); ++old) {
    if (impulses[old].isZero()) continue;
    const auto found = std::find(to.begin(), to.end(), from[old]);
    if (found != to.end()) carried[found - to.begin()] = impulses[old];
  }
}

ProximityCertifier::ProximityCertifier(const MeshCcd& ccd, const ContactSettings& settings,
                                       const Vec3& centre_of_mass)
    : ccd_(ccd),
      settings_(settings),
      frames_{centre_of_mass},
      radius_(settings.point_tool ? 0.0 : ccd.tool_radius()) {}

ProximityCertificate ProximityCertifier::certify(QueryWorkspace& queries, const Pose& tool_pose,
                                                 double band_m) const {
  ProximityCertificate certificate;
  certificate.anchor = frames_.com_frame(tool_pose);
  certificate.ahead_searches = advance_search_ahead(queries, certificate.anchor) ? 1 : 0;
  const auto most = static_cast<std::size_t>(settings_.haptic_max_pairs);
  const std::size_t first = std::min(kFirstListedPairs, most);
  constexpr double kReachPerBand = 1.0 / 3;
  const double reach_wanted = kReachPerBand * band_m;
  // A list cut short at `clearance` (< band_m) that leaves too little reach:
  // pairs crowd the standoff.
  const auto too_little_reach = [&](double clearance) {
    return clearance < band_m && clearance - settings_.standoff_m < reach_wanted;
  };
  std::size_t listed = queries.crowded_ ? most : first;
  ProximityResult found = listed_pairs(queries, certificate.anchor, band_m, listed,
                                       certificate.searches, certificate.ahead_searches);
  if (!queries.crowded_ && first < most && too_little_reach(found.clearance_m)) {
    listed = most;
    found = listed_pairs(queries, certificate.anchor, band_m, listed, certificate.searches,
                         certificate.ahead_searches);
  }
  // Whether the first pairs alone would have left too little reach here
  // (their clearance: the distance of the next pair): then the next query,
  // a slow-loop interval away, lists the most at once.
  queries.crowded_ = found.pairs.size() > first && too_little_reach(found.pairs[first].distance);
  // A wider search pays while the next certificates come from its pairs;
  // when the one after it had to search as well (the tool moves faster than
  // the margin, as in an impact), searches ask only for what they need,
  // trying a wider one again after kPlainSearchesBetweenTries of them.
  if (certificate.searches == 0)
    queries.widen_ = true;
  else if (queries.last_search_widened_)
    queries.widen_ = false;
  queries.last_search_widened_ = certificate.searches > 0 && queries.searched_.widened;
  certificate.clearance_m = found.clearance_m;
  certificate.pairs.reserve(found.pairs.size());
  certificate.distances.reserve(found.pairs.size());
  for (const ProximityPair& pair : found.pairs) {
    certificate.pairs.push_back(pair.features);
    certificate.distances.push_back(pair.distance);
  }
  if (!queries.listed_groups_.empty()) mark_repeats(queries, certificate);
  start_search_ahead(queries, certificate, band_m, listed);
  queries.last_anchor_ = certificate.anchor;
  queries.last_clearance_m_ = certificate.clearance_m;
  return certificate;
}

std::size_t ProximityCertifier::pairs_kept(std::size_t max_pairs, std::size_t per_listed) const {
  return std::max(max_pairs, std::min(per_listed * max_pairs,
                                      static_cast<std::size_t>(settings_.haptic_max_pairs)));
}

double ProximityCertifier::queries_left(const QueryWorkspace& queries, const Pose& anchor) const {
  if (!queries.last_anchor_) return std::numeric_limits<double>::infinity();
  const double step = point_reach(displacement(*queries.last_anchor_, anchor), radius_);
  if (!(step > 0)) return std::numeric_limits<double>::infinity();
  const double room = queries.searched_.clearance_m -
                      point_reach(displacement(queries.searched_.anchor, anchor), radius_) -
                      queries.last_clearance_m_;
  return std::max(0.0, std::floor(room / step));
}

void ProximityCertifier::start_search_ahead(QueryWorkspace& queries,
                                            const ProximityCertificate& certificate, double band_m,
                                            std::size_t max_pairs) const {
  // Only near the scene (in free space the clearance is the reach), with
  // room beyond what the query needed, and once the queries left are few
  // enough to need it but enough to share it: a proxy at rest keeps its
  // pairs, and one that outruns every search (an impact) searches as it goes.
  if (queries.ahead_ || queries.searched_.pairs.empty() || queries.search_node_pairs_ == 0 ||
      !queries.last_anchor_ || !(queries.searched_.clearance_m > queries.last_clearance_m_))
    return;
  const double left = queries_left(queries, certificate.anchor);
  if (!(left <= kAheadLeadQueries && left >= kAheadLeastQueries)) return;
  // Centred where the tool will be when the kept pairs run out, at its
  // motion per query, so that the new pairs' room lies ahead of it.
  const Pose anchor =
      displaced(certificate.anchor, left * displacement(*queries.last_anchor_, certificate.anchor));
  queries.ahead_.emplace(
      SearchAhead{ccd_.start_proximity(anchor, (1 + kAheadMargin) * band_m,
                                       pairs_kept(max_pairs, kAheadPairsPerListed)),
                  anchor});
}

bool ProximityCertifier::advance_search_ahead(QueryWorkspace& queries, const Pose& anchor) const {
  if (!queries.ahead_) return false;
  // The rest of the node pairs the last search opened, shared among this
  // query and those left; at least kAheadLeastSlice, at most a slice.
  int64_t slice = kAheadLeastSlice;
  const double left = queries_left(queries, anchor);
  if (std::isfinite(left)) {
    const int64_t remaining =
        std::max(queries.search_node_pairs_ - queries.ahead_->search.opened(), kAheadLeastSlice);
    slice = std::clamp(static_cast<int64_t>(std::ceil(static_cast<double>(remaining) / (left + 1))),
                       kAheadLeastSlice, kAheadSliceNodePairs);
  }
  if (!queries.ahead_->search.advance(slice)) return false;
  return complete_search_ahead(queries);
}

bool ProximityCertifier::complete_search_ahead(QueryWorkspace& queries) const {
  if (!queries.ahead_) return false;
  SearchAhead ahead = std::move(*queries.ahead_);
  queries.ahead_.reset();
  keep_search(queries, ahead.anchor, std::move(ahead.search), true);
  return true;
}

void ProximityCertifier::QueryWorkspace::forget() {
  ahead_.reset();
  search_node_pairs_ = 0;
  last_anchor_.reset();
  last_clearance_m_ = 0;
  searched_ = SearchedPairs{};
  crowded_ = false;
  widen_ = true;
  plain_searches_ = 0;
  last_search_widened_ = false;
}

void ProximityCertifier::mark_repeats(QueryWorkspace& queries,
                                      ProximityCertificate& certificate) const {
  // The listed pairs' groups (from the search): the first listed pair of a
  // group is measured, the others repeat it.
  std::vector<int>& firsts = certificate.first_of_kind;
  std::vector<int>& measured_as = certificate.measured_as;
  firsts.clear();
  measured_as.resize(queries.listed_groups_.size());
  for (std::size_t k = 0; k < queries.listed_groups_.size(); ++k) {
    int& first = queries.group_first_[static_cast<std::size_t>(queries.listed_groups_[k])];
    if (first < 0) {
      first = static_cast<int>(firsts.size());
      firsts.push_back(static_cast<int>(k));
    }
    measured_as[k] = first;
  }
  for (const int group : queries.listed_groups_)
    queries.group_first_[static_cast<std::size_t>(group)] = -1;
  if (firsts.size() == measured_as.size()) {
    firsts.clear();
    measured_as.clear();
  }
}

void ProximityCertifier::group_searched_pairs(QueryWorkspace& queries) const {
  // Pairs of one kind and tool feature whose scene features share a place
  // (MeshCcd::scene_feature_places) form a group; every other pair is one.
  std::vector<int>& group = queries.searched_.group;
  group.clear();
  if (!ccd_.scene_features_share_places()) return;
  const std::vector<ProximityPair>& pairs = queries.searched_.pairs;
  queries.features_.clear();
  for (const ProximityPair& pair : pairs) queries.features_.push_back(pair.features);
  ccd_.scene_feature_places(queries.features_, queries.places_);
  std::size_t table = 64;
  while (table < 2 * pairs.size()) table *= 2;
  std::vector<int>& slots = queries.group_first_;  // its −1 state is restored below
  slots.assign(table, -1);
  group.resize(pairs.size());
  int groups = 0;
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    const ContactFeatures& pair = queries.features_[k];
    const int place = queries.places_[k];
    if (place < 0) {  // alone at its place: a group of its own
      group[k] = groups++;
      continue;
    }
    const uint64_t key = (static_cast<uint64_t>(pair.kind) << 62) ^
                         (static_cast<uint64_t>(static_cast<uint32_t>(pair.tool_feature)) << 31) ^
                         static_cast<uint64_t>(static_cast<uint32_t>(place));
    std::size_t slot = (key * 0x9E3779B97F4A7C15ULL >> 20) & (table - 1);
    int found = -1;
    for (; slots[slot] >= 0; slot = (slot + 1) & (table - 1)) {
      const auto other = static_cast<std::size_t>(slots[slot]);
      if (queries.features_[other].kind == pair.kind &&
          queries.features_[other].tool_feature == pair.tool_feature &&
          queries.places_[other] == place) {
        found = group[other];
        break;
      }
    }
    if (found < 0) {
      slots[slot] = static_cast<int>(k);
      found = groups++;
    }
    group[k] = found;
  }
  queries.group_first_.assign(static_cast<std::size_t>(std::max(groups, 1)), -1);
  queries.group_slot_.assign(queries.group_first_.size(), -1);
}

namespace {

// The first `count` entries of `order` (distance, index of a pair whose
// features are features_of(index)) in the order proximity lists pairs
// (nearer(): ties by features), the rest dropped, as far as they are read:
// the same list whichever search the pairs came from.
template <class FeaturesOf>
void keep_nearest(std::vector<std::pair<double, int>>& order, std::size_t count,
                  FeaturesOf&& features_of) {
  // nearer(), without building the pairs.
  const auto before = [&](const std::pair<double, int>& a, const std::pair<double, int>& b) {
    return a.first < b.first ||
           (a.first == b.first && features_of(b.second) < features_of(a.second));
  };
  if (order.size() > count) {
    std::nth_element(order.begin(), order.begin() + static_cast<std::ptrdiff_t>(count), order.end(),
                     before);
    order.resize(count);
  }
  std::sort(order.begin(), order.end(), before);
}

// The max_pairs nearest of `nearest` (ascending distances) within band_m,
// when `nearest` holds every pair nearer than `complete` (m): all of them
// within band_m when complete reaches band_m, else max_pairs + 1 of them
// within `complete`, the last giving the clearance; none otherwise.
std::optional<ProximityResult> answer_within(std::span<const ProximityPair> nearest,
                                             double complete, double band_m,
                                             std::size_t max_pairs) {
  const double within = std::min(complete, band_m);
  const auto inside = static_cast<std::size_t>(
      std::find_if(nearest.begin(), nearest.end(),
                   [&](const ProximityPair& pair) { return pair.distance > within; }) -
      nearest.begin());
  ProximityResult answer;
  if (inside > max_pairs)
    answer.clearance_m = nearest[max_pairs].distance;
  else if (complete >= band_m)
    answer.clearance_m = band_m;
  else
    return std::nullopt;
  answer.pairs.assign(nearest.begin(),
                      nearest.begin() + static_cast<std::ptrdiff_t>(std::min(inside, max_pairs)));
  return answer;
}

}  // namespace

ProximityResult ProximityCertifier::listed_pairs(QueryWorkspace& queries, const Pose& anchor,
                                                 double band_m, std::size_t max_pairs,
                                                 int& searches, int& ahead_searches) const {
  if (std::optional<ProximityResult> answer =
          answer_from_searched(queries, anchor, band_m, max_pairs))
    return std::move(*answer);
  // A search ahead, completed here if it is at least half done (else a
  // search of what the query needs costs less), may answer.
  if (queries.ahead_ && 2 * queries.ahead_->search.opened() < queries.search_node_pairs_)
    queries.ahead_.reset();
  if (complete_search_ahead(queries)) {
    ++ahead_searches;
    if (std::optional<ProximityResult> answer =
            answer_from_searched(queries, anchor, band_m, max_pairs))
      return std::move(*answer);
  }
  ++searches;
  // Farther than asked and up to twice the pairs (within the most a query
  // lists), so that the next queries can be answered from the pairs found
  // (certify says when).
  const bool widened = queries.widen_ || queries.plain_searches_ >= kPlainSearchesBetweenTries;
  queries.plain_searches_ = widened ? 0 : queries.plain_searches_ + 1;
  const std::size_t kept = widened ? pairs_kept(max_pairs, kSearchedPairsPerListed) : max_pairs;
  keep_search(queries, anchor,
              ccd_.start_proximity(anchor, (widened ? 1 + kSearchMargin : 1.0) * band_m, kept),
              widened);
  // The search holds every pair nearer than its clearance, and more than
  // max_pairs of them if it was cut short beyond max_pairs; cut short at
  // max_pairs, its list and clearance are the answer.
  std::optional<ProximityResult> answer =
      answer_within(queries.searched_.pairs, queries.searched_.clearance_m, band_m, max_pairs);
  if (!answer || queries.searched_.pairs.empty()) {  // cut short, or free space (its clearance)
    answer.emplace();
    answer->pairs = queries.searched_.pairs;
    answer->clearance_m = queries.searched_.clearance_m;
  }
  // The answer is a prefix of the searched pairs.
  const std::vector<int>& group = queries.searched_.group;
  queries.listed_groups_.assign(
      group.begin(),
      group.begin() + static_cast<std::ptrdiff_t>(group.empty() ? 0 : answer->pairs.size()));
  return std::move(*answer);
}

void ProximityCertifier::keep_search(QueryWorkspace& queries, const Pose& anchor,
                                     ProximityInSlices search, bool widened) const {
  search.advance(std::numeric_limits<int64_t>::max());
  queries.search_node_pairs_ = search.opened();
  ProximityResult found = search.finish();
  // Nothing near: how far the scene is (up to kFreeSpaceReachBands widest
  // bands), so that the proxy may go that far before the next certificate
  // (a late slow loop must not hold it back in free space). A lower bound
  // serves as well as the distance: the best-first search's after
  // kFreeSpaceNodePairs node pairs.
  if (found.pairs.empty()) {
    ProximityInSlices nearest =
        ccd_.start_proximity(anchor, kFreeSpaceReachBands * settings_.haptic_band_m, 0);
    nearest.advance(kFreeSpaceNodePairs);
    found.clearance_m = std::max(found.clearance_m, nearest.nearest_bound());
  }
  queries.searched_.anchor = anchor;
  queries.searched_.widened = widened;
  queries.searched_.clearance_m = found.clearance_m;
  queries.searched_.pairs = std::move(found.pairs);
  group_searched_pairs(queries);
}

std::optional<ProximityResult> ProximityCertifier::answer_from_searched(
    QueryWorkspace& queries, const Pose& anchor, double band_m, std::size_t max_pairs) const {
  if (queries.searched_.clearance_m < 0) return std::nullopt;
  // Every pair the search did not find was at least its clearance apart at
  // its pose, and no tool point has moved farther than `moved` since: here
  // it is at least `complete` apart, so the searched pairs hold every pair
  // nearer than that (less a nanometre for the rounding of the bound).
  constexpr double kRoundingSlack = 1e-9;  // m
  const double moved = point_reach(displacement(queries.searched_.anchor, anchor), radius_);
  const double complete = queries.searched_.clearance_m - moved - kRoundingSlack;
  // The answer needs every pair within band_m, or max_pairs + 1 pairs
  // within `complete` (then the last of them is the clearance).
  if (complete < band_m && queries.searched_.pairs.size() <= max_pairs) return std::nullopt;
  // In free space the clearance is the reach: measured again once the tool
  // has moved half of it away, so a late certificate still reaches far.
  if (queries.searched_.pairs.empty() && moved > 0.5 * queries.searched_.clearance_m)
    return std::nullopt;
  const double within = std::min(complete, band_m);
  // A pair's distance has changed by `moved` at most: only those that can
  // be within reach are measured again (with groups, measure_grouped picks
  // them).
  const double reachable = within + kRoundingSlack;
  const std::vector<int>& group = queries.searched_.group;
  // answer_within reads the max_pairs + 1 nearest at most (all are within).
  const std::size_t needed = max_pairs + (max_pairs < SIZE_MAX ? 1 : 0);
  std::size_t pair_tests = 0;
  if (group.empty()) {
    queries.to_measure_.clear();
    for (const ProximityPair& pair : queries.searched_.pairs)
      if (!(pair.distance - moved > reachable)) queries.to_measure_.push_back(pair.features);
    pair_tests = queries.to_measure_.size();
    ccd_.closest_points(queries.to_measure_, anchor, queries.measured_points_);
    queries.order_.clear();
    for (std::size_t i = 0; i < queries.to_measure_.size(); ++i)
      if (queries.measured_points_[i].distance <= within)
        queries.order_.push_back(
            std::pair<double, int>{queries.measured_points_[i].distance, static_cast<int>(i)});
    keep_nearest(queries.order_, needed, [&](int i) -> const ContactFeatures& {
      return queries.to_measure_[static_cast<std::size_t>(i)];
    });
    queries.measured_.clear();
    for (const auto& [distance, i] : queries.order_)
      queries.measured_.push_back(
          ProximityPair{queries.to_measure_[static_cast<std::size_t>(i)], distance});
    queries.listed_groups_.clear();
  } else {
    measure_grouped(queries, anchor, moved, reachable, within, needed);
    pair_tests = queries.measured_index_.size();
  }
  std::optional<ProximityResult> answer =
      answer_within(queries.measured_, complete, band_m, max_pairs);
  if (answer && queries.searched_.pairs.empty()) answer->clearance_m = complete;  // free space
  if (answer) answer->pair_tests = static_cast<int64_t>(pair_tests);
  if (!group.empty())
    queries.listed_groups_.resize(answer ? answer->pairs.size() : 0);  // a prefix of measured_'s
  return answer;
}

void ProximityCertifier::measure_grouped(QueryWorkspace& queries, const Pose& anchor, double moved,
                                         double reachable, double within,
                                         std::size_t needed) const {
  // As the plain re-measurement (answer_from_searched), the first pair of
  // each group measured for all of it: the same distances, bit for bit.
  const std::vector<ProximityPair>& pairs = queries.searched_.pairs;
  const std::vector<int>& group = queries.searched_.group;
  queries.firsts_measured_.clear();
  queries.measured_index_.clear();
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    if (pairs[i].distance - moved > reachable) continue;
    int& slot = queries.group_slot_[static_cast<std::size_t>(group[i])];
    if (slot < 0) {
      slot = static_cast<int>(queries.firsts_measured_.size());
      queries.firsts_measured_.push_back(pairs[i].features);
    }
    queries.measured_index_.push_back(static_cast<int>(i));
  }
  ccd_.closest_points(queries.firsts_measured_, anchor, queries.measured_points_);
  queries.order_.clear();
  for (const int i : queries.measured_index_) {
    const int slot =
        queries.group_slot_[static_cast<std::size_t>(group[static_cast<std::size_t>(i)])];
    if (queries.measured_points_[static_cast<std::size_t>(slot)].distance <= within)
      queries.order_.push_back(std::pair<double, int>{
          queries.measured_points_[static_cast<std::size_t>(slot)].distance, i});
  }
  for (const int i : queries.measured_index_)
    queries.group_slot_[static_cast<std::size_t>(group[static_cast<std::size_t>(i)])] = -1;
  keep_nearest(queries.order_, needed, [&](int i) -> const ContactFeatures& {
    return pairs[static_cast<std::size_t>(i)].features;
  });
  queries.measured_.clear();
  queries.listed_groups_.clear();
  for (const auto& [distance, i] : queries.order_) {
    queries.measured_.push_back(
        ProximityPair{pairs[static_cast<std::size_t>(i)].features, distance});
    queries.listed_groups_.push_back(group[static_cast<std::size_t>(i)]);
  }
}

double ProximityCertifier::band_for(const Pose& previous_target, const Pose& target) const {
  constexpr double kMargin = 6.0;  // two intervals until the next certificate, times three
  const double moved = point_reach(
      displacement(frames_.com_frame(previous_target), frames_.com_frame(target)), radius_);
  return std::clamp(kMargin * moved, settings_.haptic_band_min_m, settings_.haptic_band_m);
}

bool ProximityCertifier::within_reach(const ProximityCertificate& certificate,
                                      const Pose& tool_pose) const {
  return point_reach(displacement(certificate.anchor, frames_.com_frame(tool_pose)), radius_) <=
         reach(certificate);
}

PairContact ProximityCertifier::evaluate(const ContactFeatures& pair, const Pose& com_pose) const {
  return contact_of(pair, ccd_.closest_points(pair, com_pose), com_pose);
}

void ProximityCertifier::evaluate(EvaluationWorkspace& workspace,
                                  std::span<const ContactFeatures> pairs, const Pose& com_pose,
                                  std::vector<PairContact>& contacts) const {
  ccd_.closest_points(pairs, com_pose, workspace.points_);
  contacts.resize(pairs.size());
  for (std::size_t k = 0; k < pairs.size(); ++k)
    contacts[k] = contact_of(pairs[k], workspace.points_[k], com_pose);
}

void ProximityCertifier::evaluate_listed(EvaluationWorkspace& workspace,
                                         const ProximityCertificate& certificate, std::size_t count,
                                         const Pose& com_pose,
                                         std::vector<PairContact>& contacts) const {
  const std::span<const ContactFeatures> listed =
      std::span<const ContactFeatures>(certificate.pairs).first(count);
  if (certificate.measured_as.empty()) {
    evaluate(workspace, listed, com_pose, contacts);
    return;
  }
  // The pairs that repeat none among the first `count`: a prefix of
  // first_of_kind (a pair comes after the one it repeats).
  const std::vector<int>& firsts = certificate.first_of_kind;
  const auto measured = static_cast<std::size_t>(
      std::lower_bound(firsts.begin(), firsts.end(), static_cast<int>(count)) - firsts.begin());
  workspace.firsts_.clear();
  for (std::size_t i = 0; i < measured; ++i)
    workspace.firsts_.push_back(listed[static_cast<std::size_t>(firsts[i])]);
  ccd_.closest_points(workspace.firsts_, com_pose, workspace.points_);
  contacts.resize(count);
  for (std::size_t k = 0; k < count; ++k) {
    const auto as = static_cast<std::size_t>(certificate.measured_as[k]);
    const auto first = static_cast<std::size_t>(firsts[as]);
    const PairClosestPoints& points = workspace.points_[as];
    // Away from the floor the contact is the points' alone (contact_of):
    // the first's, bit for bit.
    contacts[k] = first < k && points.distance > kDirectionFloor
                      ? contacts[first]
                      : contact_of(listed[k], points, com_pose);
  }
}

PairContact ProximityCertifier::contact_of(const ContactFeatures& pair,
                                           const PairClosestPoints& points,
                                           const Pose& com_pose) const {
  PairContact contact;
  contact.scene_point = points.scene_point;
  contact.tool_point = points.tool_point;
  contact.distance = points.distance;
  contact.normal = points.distance > kDirectionFloor
                       ? Vec3((points.tool_point - points.scene_point) / points.distance)
                       : ccd_.evaluate(pair, com_pose).normal;
  return contact;
}

}  // namespace hb
