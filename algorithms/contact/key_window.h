// Ids kept in order of a scalar key, to visit those whose key lies within a
// radius of a value: the candidates of a "within
// distance r" search over points projected on one axis (|a·u − b·u| ≤ |a − b| for a unit u), so
// that matching contacts by position or direction costs the few near the query instead of every one
// (ConstrainedStepSolver).
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

#include "hapticbench/pose.h"

namespace hb {

class KeyWindow {
 public:
  /// A unit axis in no particular alignment with a scene's or tool's axes,
  /// so that contacts on an axis-aligned face or edge do not share one key.
  static Vec3 axis() { return Vec3(0.48, 0.6, 0.64); }

  void clear() { entries_.clear(); }
  /// Holds ids 0 … n − 1 with keys key_of(id), sorted. A NaN key (a
  /// non-finite lever) is held as +∞, so that the order stays strict; no
  /// finite key's window reaches it.
  template <class KeyOf>
  void assign(std::size_t n, KeyOf&& key_of) {
    entries_.clear();
    for (std::size_t id = 0; id < n; ++id) {
      const double key = key_of(static_cast<int>(id));
      entries_.emplace_back(std::isnan(key) ? std::numeric_limits<double>::infinity() : key,
                            static_cast<int>(id));
    }
    std::sort(entries_.begin(), entries_.end());
  }
  /// Adds id with key `key` (NaN held as +∞), keeping the order.
  void insert(double key, int id) {
    const Entry entry(std::isnan(key) ? std::numeric_limits<double>::infinity() : key, id);
    entries_.insert(std::upper_bound(entries_.begin(), entries_.end(), entry), entry);
  }
  /// Calls visit(id), in ascending order of id, for every id whose key is
  /// within [key − radius, key + radius], until visit returns false.
  template <class Visit>
  void visit_within(double key, double radius, Visit&& visit) {
    auto it = std::lower_bound(entries_.begin(), entries_.end(), key - radius,
                               [](const Entry& e, double k) { return e.first < k; });
    ids_.clear();
    for (; it != entries_.end() && it->first <= key + radius; ++it) ids_.push_back(it->second);
    // Ids of equal keys come in ascending order already: a window of one
    // key (contacts on one face share a normal) needs no sort.
    if (!std::is_sorted(ids_.begin(), ids_.end())) std::sort(ids_.begin(), ids_.end());
    for (const int id : ids_)
      if (!visit(id)) return;
  }
  /// The least id whose key is within [key − radius, key + radius] and
  /// for which accept(id) holds, −1 if none: what visiting the window in
  /// ascending order of id until the first accepted one finds, without
  /// putting the window in that order (accept is asked only of ids below
  /// the least accepted so far).
  template <class Accept>
  int least_within(double key, double radius, Accept&& accept) const {
    auto it = std::lower_bound(entries_.begin(), entries_.end(), key - radius,
                               [](const Entry& e, double k) { return e.first < k; });
    int least = -1;
    for (; it != entries_.end() && it->first <= key + radius; ++it)
      if ((least < 0 || it->second < least) && accept(it->second)) least = it->second;
    return least;
  }
  std::size_t size() const { return entries_.size(); }
  /// The ids in order of key (equal keys by ascending id).
  template <class Visit>
  void visit_in_key_order(Visit&& visit) const {
    for (const Entry& entry : entries_) visit(entry.second);
  }

 private:
  // Plain data (not std::pair, whose assignment is user-provided), so that
  // insert moves the entries after it as one block of bytes.
  struct Entry {
    double first;  ///< key
    int second;    ///< id
    Entry(double key, int id) : first(key), second(id) {}
    bool operator<(const Entry& other) const {
      return first < other.first || (first == other.first && second < other.second);
    }
  };
  std::vector<Entry> entries_;
  std::vector<int> ids_;  ///< the ids near one key, sorted
};

}  // namespace hb
