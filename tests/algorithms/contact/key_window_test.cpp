// KeyWindow visits what a scan of every id would accept: every point within
// the radius of the query (by key on KeyWindow::axis()), in ascending order
// of id, and stops when asked; least_within finds the first it would stop at.
#include "algorithms/contact/key_window.h"

#include <algorithm>
#include <catch2/catch.hpp>
#include <limits>
#include <random>
#include <vector>

namespace {

using hb::KeyWindow;
using hb::Vec3;

TEST_CASE("a key window finds every point within the radius, in order of id") {
  std::mt19937 random(5);
  std::uniform_real_distribution<double> unit(-1, 1);
  for (const double spread : {1e-3, 1.0}) {
    // Clustered points (many sharing nearly one key) and spread ones.
    std::vector<Vec3> points;
    for (int i = 0; i < 400; ++i) {
      const Vec3 centre = i % 2 ? Vec3(0.1, 0.2, 0.3) : Vec3::Zero();
      points.push_back(centre + spread * Vec3(unit(random), unit(random), unit(random)));
    }
    KeyWindow window;
    window.assign(points.size(), [&](int i) { return points[i].dot(KeyWindow::axis()); });
    REQUIRE(window.size() == points.size());
    const double radius = 0.3 * spread;
    for (std::size_t q = 0; q < points.size(); q += 7) {
      std::vector<int> near, visited;
      for (std::size_t i = 0; i < points.size(); ++i)
        if ((points[i] - points[q]).norm() <= radius) near.push_back(static_cast<int>(i));
      window.visit_within(points[q].dot(KeyWindow::axis()), radius, [&](int id) {
        if ((points[id] - points[q]).norm() <= radius) visited.push_back(id);
        return true;
      });
      INFO("spread " << spread << ", query " << q);
      CHECK(visited == near);  // the same ids, ascending
      // Stopped at the first: the smallest id near the query.
      int first = -1;
      window.visit_within(points[q].dot(KeyWindow::axis()), radius, [&](int id) {
        if ((points[id] - points[q]).norm() > radius) return true;
        first = id;
        return false;
      });
      CHECK(first == near.front());
      // The least accepted id, the window left in key order: the same, and
      // for a test that takes only odd ids, the least odd one near.
      const auto is_near = [&](int id) { return (points[id] - points[q]).norm() <= radius; };
      CHECK(window.least_within(points[q].dot(KeyWindow::axis()), radius, is_near) == first);
      const auto odd = std::find_if(near.begin(), near.end(), [](int id) { return id % 2 == 1; });
      CHECK(window.least_within(points[q].dot(KeyWindow::axis()), radius, [&](int id) {
        return id % 2 == 1 && is_near(id);
      }) == (odd == near.end() ? -1 : *odd));
    }
  }
}

TEST_CASE("a key window filled one id at a time visits what one filled at once does") {
  // ConstrainedStepSolver adds the groups' first rows as it makes them.
  std::mt19937 random(9);
  std::uniform_real_distribution<double> unit(-1, 1);
  std::vector<Vec3> points;
  for (int i = 0; i < 300; ++i)  // a third share one point: equal keys
    points.push_back(i % 3 == 0 ? Vec3(0.2, 0.1, 0) : Vec3(unit(random), unit(random), 0) * 1e-2);
  const auto key = [&](int i) { return points[i].dot(KeyWindow::axis()); };
  KeyWindow at_once, one_by_one;
  at_once.assign(points.size(), key);
  for (std::size_t i = 0; i < points.size(); ++i) one_by_one.insert(key(i), static_cast<int>(i));
  REQUIRE(one_by_one.size() == points.size());
  for (std::size_t q = 0; q < points.size(); q += 5) {
    std::vector<int> a, b;
    at_once.visit_within(key(q), 2e-3, [&](int id) {
      a.push_back(id);
      return true;
    });
    one_by_one.visit_within(key(q), 2e-3, [&](int id) {
      b.push_back(id);
      return true;
    });
    INFO("query " << q);
    CHECK(a == b);
    CHECK(std::is_sorted(a.begin(), a.end()));
  }
}

TEST_CASE("a key window holds non-finite points apart from the others") {
  // A NaN key would break the sort's order; it is held as +∞.
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<Vec3> points = {Vec3(0, 0, 0), Vec3(nan, 0, 0), Vec3(1e-4, 0, 0),
                                    Vec3(std::numeric_limits<double>::infinity(), 0, 0)};
  KeyWindow window;
  window.assign(points.size(), [&](int i) { return points[i].dot(KeyWindow::axis()); });
  std::vector<int> visited;
  window.visit_within(0.0, 1e-3, [&](int id) {
    visited.push_back(id);
    return true;
  });
  CHECK(visited == std::vector<int>{0, 2});
  visited.clear();
  window.visit_within(nan, 1e-3, [&](int id) {
    visited.push_back(id);
    return true;
  });
  CHECK(visited.empty());
}

}  // namespace
