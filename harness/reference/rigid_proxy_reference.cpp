#include "harness/reference/rigid_proxy_reference.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <span>

#include "hapticbench/closest_points.h"
#include "harness/reference/contact_support.h"
#include "harness/reference/surface_samples.h"

namespace hb {

namespace {

using MatX = Eigen::MatrixXd;
using VecX = Eigen::VectorXd;

// Lawson–Hanson non-negative least squares: u ≥ 0 minimising |E u − f|.
// E has at most kNnlsRows rows and any number of columns; the passive set never
// holds more columns than the rank allows (kMaxPassive bounds it where
// rounding would let a dependent column in), so its systems live on the
// stack.
constexpr int kNnlsRows = 7;
constexpr int kMaxPassive = 16;
VecX non_negative_least_squares(const MatX& e, const VecX& f) {
  using PassiveMatrix =
      Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kNnlsRows, kMaxPassive>;
  using PassiveVector = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxPassive, 1>;
  const Eigen::Index m = e.cols();
  VecX u = VecX::Zero(m), z = VecX::Zero(m), w(m);
  std::vector<uint8_t> passive(static_cast<std::size_t>(m), 0);
  const double scale = std::max(1.0, e.cwiseAbs().maxCoeff()) * std::max(1.0, f.norm());
  const double tolerance = 1e-13 * scale;
  std::array<Eigen::Index, kMaxPassive> columns{};
  int count = 0;
  PassiveMatrix ep;
  // Householder QR for the passive set's independent columns; a rank-
  // revealing one (least norm) where rounding let a dependent one in.
  Eigen::HouseholderQR<PassiveMatrix> decomposition;
  Eigen::CompleteOrthogonalDecomposition<PassiveMatrix> rank_revealing;
  const auto solve_passive = [&] {
    count = 0;
    for (Eigen::Index j = 0; j < m; ++j)
      if (passive[static_cast<std::size_t>(j)]) columns[static_cast<std::size_t>(count++)] = j;
    z.setZero();
    if (count == 0) return;
    ep.resize(e.rows(), count);
    for (int k = 0; k < count; ++k) ep.col(k) = e.col(columns[static_cast<std::size_t>(k)]);
    decomposition.compute(ep);
    const auto diagonal = decomposition.matrixQR().diagonal().cwiseAbs();
    PassiveVector zp;
    if (count <= e.rows() && diagonal.minCoeff() > 1e-10 * diagonal.maxCoeff()) {
      zp = decomposition.solve(f);
    } else {
      rank_revealing.compute(ep);
      zp = rank_revealing.solve(f);
    }
    for (int k = 0; k < count; ++k) z[columns[static_cast<std::size_t>(k)]] = zp[k];
  };
  int passive_count = 0;
  for (Eigen::Index outer = 0; outer < 3 * m + 10; ++outer) {
    w.noalias() = e.transpose() * (f - e * u);
    Eigen::Index best = -1;
    double best_w = tolerance;
    for (Eigen::Index j = 0; j < m; ++j)
      if (!passive[static_cast<std::size_t>(j)] && w[j] > best_w) best_w = w[j], best = j;
    if (best < 0 || passive_count == kMaxPassive) break;
    passive[static_cast<std::size_t>(best)] = 1;
    ++passive_count;
    for (int inner = 0; inner < 100; ++inner) {
      solve_passive();
      bool positive = true;
      for (int k = 0; k < count; ++k)
        positive = positive && z[columns[static_cast<std::size_t>(k)]] > 0;
      if (positive) {
        u = z;
        break;
      }
      double alpha = 1.0;
      for (int k = 0; k < count; ++k) {
        const Eigen::Index j = columns[static_cast<std::size_t>(k)];
        if (z[j] <= 0) alpha = std::min(alpha, u[j] / (u[j] - z[j]));
      }
      u += alpha * (z - u);
      for (int k = 0; k < count; ++k) {
        const Eigen::Index j = columns[static_cast<std::size_t>(k)];
        if (u[j] <= tolerance * 1e-3)
          u[j] = 0, passive[static_cast<std::size_t>(j)] = 0, --passive_count;
      }
    }
  }
  return u;
}

// An order of triangles by their corners' coordinates.
bool by_corners(const NearTriangle& x, const NearTriangle& y) {
  const auto key = [](const NearTriangle& t) {
    return std::array<double, 9>{t.corners[0].x(), t.corners[0].y(), t.corners[0].z(),
                                 t.corners[1].x(), t.corners[1].y(), t.corners[1].z(),
                                 t.corners[2].x(), t.corners[2].y(), t.corners[2].z()};
  };
  return key(x) < key(y);
}

// The mesh's sharp edges (faces meeting at more than kSharpDegrees, or an
// open boundary) as pairs of vertex indices.
constexpr double kSharpDegrees = 5.0;

std::vector<std::array<int, 2>> sharp_edges(const TriangleMesh& mesh) {
  std::vector<std::array<int, 3>> edges;  // (low vertex, high vertex, triangle)
  edges.reserve(3 * mesh.triangles.size());
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
    for (int k = 0; k < 3; ++k) {
      const int a = mesh.triangles[t][k], b = mesh.triangles[t][(k + 1) % 3];
      edges.push_back({std::min(a, b), std::max(a, b), static_cast<int>(t)});
    }
  std::sort(edges.begin(), edges.end());
  const auto normal = [&](int t) {
    const auto& [a, b, c] = mesh.triangles[static_cast<std::size_t>(t)];
    return (mesh.vertices[b] - mesh.vertices[a])
        .cross(mesh.vertices[c] - mesh.vertices[a])
        .normalized();
  };
  const double sharp_cos = std::cos(kSharpDegrees * M_PI / 180.0);
  std::vector<std::array<int, 2>> sharp;
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t j = i + 1;
    while (j < edges.size() && edges[j][0] == edges[i][0] && edges[j][1] == edges[i][1]) ++j;
    if (j - i != 2 || normal(edges[i][2]).dot(normal(edges[i + 1][2])) < sharp_cos)
      sharp.push_back({edges[i][0], edges[i][1]});
    i = j;
  }
  return sharp;
}

// The points dividing the edge [a, b] into pieces no longer than `spacing`
// (m), from a to b, both included.
std::vector<Vec3> edge_division(const Vec3& a, const Vec3& b, double spacing) {
  const int pieces = std::max(1, static_cast<int>(std::ceil((b - a).norm() / spacing)));
  std::vector<Vec3> points;
  for (int k = 0; k <= pieces; ++k) points.push_back(a + (b - a) * (double(k) / pieces));
  return points;
}

// Points along the mesh's sharp edges, about `spacing` apart, endpoints
// excluded: with the vertices they keep a scene's ridges out of the tool
// between its own samples.
void add_sharp_edge_points(const TriangleMesh& mesh, const Pose& pose, double spacing,
                           std::vector<Vec3>& out) {
  for (const auto& [a, b] : sharp_edges(mesh)) {
    const std::vector<Vec3> points =
        edge_division(pose.transform_point(mesh.vertices[static_cast<std::size_t>(a)]),
                      pose.transform_point(mesh.vertices[static_cast<std::size_t>(b)]), spacing);
    out.insert(out.end(), points.begin() + 1, points.end() - 1);
  }
}

// Closest points of the segment [a, b] (on_p) and the triangle (on_q), m,
// one frame: the nearest of its endpoints against the triangle, the
// segment against the triangle's edges, and the point where it crosses the
// triangle's plane (distance 0 where that point is inside).
SegmentClosestPoints closest_points_of_segment_and_triangle(const Vec3& a, const Vec3& b,
                                                            const std::array<Vec3, 3>& t) {
  const auto on_triangle = [&](const Vec3& p) {
    return closest_point_on_triangle(p, t[0], t[1], t[2]);
  };
  SegmentClosestPoints best{a, on_triangle(a)};
  const auto consider = [&](const Vec3& p, const Vec3& q) {
    if ((p - q).squaredNorm() < (best.on_p - best.on_q).squaredNorm()) best = {p, q};
  };
  consider(b, on_triangle(b));
  for (int k = 0; k < 3; ++k) {
    const SegmentClosestPoints edge = closest_points_of_segments(a, b, t[k], t[(k + 1) % 3]);
    consider(edge.on_p, edge.on_q);
  }
  const Vec3 n = (t[1] - t[0]).cross(t[2] - t[0]);
  const double da = n.dot(a - t[0]), db = n.dot(b - t[0]);
  if ((da < 0) != (db < 0)) {
    const Vec3 crossing = a + (b - a) * (da / (da - db));
    consider(crossing, on_triangle(crossing));
  }
  return best;
}

// Which of a point's near triangles need no row of their own: triangle k,
// whose point nearest the query (`to[k]`, from `from[k]` on the query's
// side) lies on its boundary, is implied by a triangle j whose nearest
// point is interior (the row is j's plane) when triangle k lies wholly on
// or behind that plane (a coplanar neighbour, a convex surface): keeping
// the query ε in front of the plane keeps it ε from triangle k. Dropped,
// the boundary row's tilted normal cannot make a false corner where two
// coplanar triangles meet (with friction, a corner that jams a sliding
// contact; without, one that leans on it). All arguments in one frame.
std::vector<char> implied_triangles(std::span<const Vec3> from, std::span<const Vec3> to,
                                    std::span<const std::array<Vec3, 3>> corners) {
  constexpr double kBehindM = 1e-10;  // m: "on the plane" for rounding
  const std::size_t n = corners.size();
  std::vector<char> implied(n, 0);
  if (n < 2) return implied;
  std::vector<Vec3> plane_normal(n, Vec3::Zero());  // unit, toward the query; 0 if not interior
  for (std::size_t j = 0; j < n; ++j) {
    const Vec3 out = from[j] - to[j];
    const Vec3 normal = (corners[j][1] - corners[j][0]).cross(corners[j][2] - corners[j][0]);
    if (!(out.norm() > 0) || !(normal.norm() > 0)) continue;
    const double along = normal.normalized().dot(out.normalized());
    if (std::abs(along) >= 1 - 1e-9)
      plane_normal[j] = (along > 0 ? 1.0 : -1.0) * normal.normalized();
  }
  for (std::size_t k = 0; k < n; ++k) {
    if (!plane_normal[k].isZero()) continue;  // interior rows are always kept
    for (std::size_t j = 0; j < n && !implied[k]; ++j) {
      if (j == k || plane_normal[j].isZero()) continue;
      bool behind = true;
      for (const Vec3& c : corners[k])
        behind = behind && plane_normal[j].dot(c - to[j]) <= kBehindM;
      implied[k] = behind;
    }
  }
  return implied;
}

// Sets distance[indices[k]] to the exact distance of points[k] from the
// oracle's surface, or to max_distance where that is nearer (a lower
// bound: a search that stops there costs far less than one that goes on).
void refresh_distances(const Oracle& oracle, std::span<const Vec3> points,
                       std::span<const std::size_t> indices, double max_distance,
                       std::vector<double>& distance) {
  if (points.empty()) return;
  PointQueryResult result;
  oracle.query_points(
      {.points = points, .want_inside = false, .want_closest = true, .max_distance = max_distance},
      result);
  for (std::size_t k = 0; k < indices.size(); ++k)
    if (result.distance[k] >= 0) distance[indices[k]] = result.distance[k];
}

}  // namespace

/// n·(δx + φ × r) ≥ b, written as a·δ ≥ b with a = (n, r × n).
struct RigidProxyReference::Row {
  Vec3 point = Vec3::Zero();  ///< m, world: where the contact acts (on the scene side)
  Vec6 a;
  double b = 0;         ///< m: ε − d
  double distance = 0;  ///< m: d
  double friction = 0;  ///< Coulomb μ of the scene object in this contact
};

RigidProxyReference::RigidProxyReference(const std::vector<SceneObject>& scene,
                                         const TriangleMesh& tool_mesh, const CouplingGains& gains,
                                         const RigidProxySettings& settings)
    : settings_(settings), gains_(gains) {
  scene_ = make_embree_oracle(scene);
  SceneObject tool;
  tool.name = "tool";
  tool.mesh = tool_mesh;
  tool.distance_only = true;  // distances to its surface only
  tool_ = make_embree_oracle({tool});

  spacing_m_ = settings_.sample_spacing_m > 0 ? settings_.sample_spacing_m
                                              : tool_mesh.bounds().diagonal().norm() / 40.0;
  // Every vertex (the deepest point of a polyhedral tool on a face is
  // one), then the samples between them.
  tool_samples_ = tool_mesh.vertices;
  const std::vector<Vec3> samples = sample_surface(tool_mesh, spacing_m_);
  tool_samples_.insert(tool_samples_.end(), samples.begin(), samples.end());
  for (const Vec3& s : tool_samples_) tool_radius_m_ = std::max(tool_radius_m_, s.norm());
  for (const Vec3& v : tool_mesh.vertices) tool_radius_m_ = std::max(tool_radius_m_, v.norm());
  sample_distance_.assign(tool_samples_.size(), -1.0);
  for (std::size_t i = 0; i < tool_samples_.size(); ++i) sample_queue_.push(-1.0, i);
  sample_motion_at_.assign(tool_samples_.size(), 0.0);
  for (const auto& [a, b] : sharp_edges(tool_mesh)) {
    const std::vector<Vec3> points =
        edge_division(tool_mesh.vertices[static_cast<std::size_t>(a)],
                      tool_mesh.vertices[static_cast<std::size_t>(b)], spacing_m_);
    for (std::size_t k = 0; k + 1 < points.size(); ++k)
      tool_edge_pieces_.push_back({points[k], points[k + 1]});
  }
  edge_distance_.assign(tool_edge_pieces_.size(), -1.0);
  for (std::size_t i = 0; i < tool_edge_pieces_.size(); ++i) edge_queue_.push(-1.0, i);
  edge_nearby_.resize(tool_edge_pieces_.size());
  edge_motion_at_.assign(tool_edge_pieces_.size(), 0.0);

  for (const SceneObject& object : scene) {
    for (const Vec3& v : object.mesh.vertices)
      scene_vertices_.push_back(object.pose.transform_point(v));
    add_sharp_edge_points(object.mesh, object.pose, spacing_m_, scene_vertices_);
    const double mu = settings_.friction ? object.friction : 0.0;
    object_friction_.push_back(mu);
    scene_vertex_friction_.resize(scene_vertices_.size(), mu);
  }
  vertex_distance_.assign(scene_vertices_.size(), -1.0);
  vertex_motion_at_.assign(scene_vertices_.size(), 0.0);
  cell_m_ = std::max(tool_radius_m_, 1e-4);
  vertex_cells_.reserve(scene_vertices_.size());
  for (std::size_t i = 0; i < scene_vertices_.size(); ++i) {
    const Vec3 c = (scene_vertices_[i] / cell_m_).array().floor();
    const int64_t key = (static_cast<int64_t>(c.x()) * 73856093) ^
                        (static_cast<int64_t>(c.y()) * 19349663) ^
                        (static_cast<int64_t>(c.z()) * 83492791);
    vertex_cells_.push_back({key, static_cast<int32_t>(i)});
  }
  std::sort(vertex_cells_.begin(), vertex_cells_.end());
}

RigidProxyReference::~RigidProxyReference() = default;

// One linearised distance: `out` the unit direction from the scene's point
// to the tool's, `point` the contact's point (on the scene side).
void RigidProxyReference::add_row(const Vec3& out, const Vec3& point, double distance, double mu) {
  Row row;
  row.point = point;
  row.a.head<3>() = out;
  row.a.tail<3>() = (point - proxy_->p).cross(out);
  row.b = settings_.clearance_m - distance;
  row.distance = distance;
  row.friction = mu;
  rows_.push_back(row);
}

std::vector<char> RigidProxyReference::implied_near_triangles(const Vec3& query) const {
  std::vector<Vec3> from(near_.size(), query), to;
  std::vector<std::array<Vec3, 3>> corners;
  for (const NearTriangle& t : near_) to.push_back(t.closest), corners.push_back(t.corners);
  return implied_triangles(from, to, corners);
}

// A frictional update converges at this multiple of the step tolerance.
constexpr double kFrictionalStepToleranceFactor = 10;

// Rounds of the frictional solve that may add rows its answer violates.
constexpr int kFrictionRounds = 8;

// A contact whose tool point slid less than this along its face over an
// update stuck (m: the solves' tolerance, far below a slide's tick).
constexpr double kStickSlipM = 1e-7;

double RigidProxyReference::friction_of(int32_t object) const {
  return object >= 0 ? object_friction_[static_cast<std::size_t>(object)] : 0.0;
}

void RigidProxyReference::DueQueue::push(double key, std::size_t index) {
  heap_.emplace_back(key, index);
  std::push_heap(heap_.begin(), heap_.end(), std::greater<>());
}

void RigidProxyReference::DueQueue::take(double limit, std::vector<std::size_t>& due) {
  due.clear();
  while (!heap_.empty() && heap_.front().first < limit) {
    std::pop_heap(heap_.begin(), heap_.end(), std::greater<>());
    due.push_back(heap_.back().second);
    heap_.pop_back();
  }
  std::sort(due.begin(), due.end());
}

// The slack on a DueQueue's key when the points whose bounds may have
// fallen below the band are taken, so that rounding cannot hold back one
// the exact test takes (m).
constexpr double kDueSlackM = 1e-9;

// The tool's sharp edges, piece by piece, against every scene triangle
// within the band, by exact segment–triangle distances: a tool ridge
// crossing a scene ridge between their samples keeps ε too (the samples
// alone let it sink up to half their spacing). Lower bounds are kept per
// piece as for the samples.
void RigidProxyReference::collect_edge_rows(double band) {
  const Pose& pose = *proxy_;
  std::vector<std::size_t> far_pieces;
  std::vector<Vec3> far_middles;
  std::vector<Vec3> on_piece, on_triangle;  // per near triangle: the closest points
  std::vector<std::array<Vec3, 3>> corners;
  std::vector<int32_t> objects;
  edge_queue_.take(motion_m_ + band + kDueSlackM, due_);
  for (const std::size_t i : due_) {
    if (edge_distance_[i] - (motion_m_ - edge_motion_at_[i]) >= band) continue;
    const Vec3 a = pose.transform_point(tool_edge_pieces_[i][0]);
    const Vec3 b = pose.transform_point(tool_edge_pieces_[i][1]);
    const Vec3 middle = 0.5 * (a + b);
    const double half = 0.5 * (b - a).norm();
    NearbyTriangles& nearby = edge_nearby_[i];
    const double moved = std::max((a - nearby.ends[0]).norm(), (b - nearby.ends[1]).norm());
    if (band + half + moved > nearby.reach) {  // search again, reaching a piece's length farther
      nearby.reach = band + 2 * half;
      nearby.ends = {a, b};
      scene_->triangles_within(middle, nearby.reach, nearby.triangles);
      // In one order whatever the search's (the rows' order moves the
      // frictional answer by rounding).
      std::sort(nearby.triangles.begin(), nearby.triangles.end(), by_corners);
      ++stats_.point_queries;
    }
    // The triangles within the band: only they give rows, so only they may
    // imply others.
    double least = band;
    on_piece.clear(), on_triangle.clear(), corners.clear(), objects.clear();
    for (const NearTriangle& t : nearby.triangles) {
      const SegmentClosestPoints closest = closest_points_of_segment_and_triangle(a, b, t.corners);
      const double distance = (closest.on_p - closest.on_q).norm();
      if (distance >= band) continue;
      least = std::min(least, distance);
      on_piece.push_back(closest.on_p);
      on_triangle.push_back(closest.on_q);
      corners.push_back(t.corners);
      objects.push_back(t.object);
    }
    const std::vector<char> implied = implied_triangles(on_piece, on_triangle, corners);
    for (std::size_t k = 0; k < on_piece.size(); ++k) {
      const double distance = (on_piece[k] - on_triangle[k]).norm();
      if (distance > 0 && !implied[k])
        add_row((on_piece[k] - on_triangle[k]) / distance, on_triangle[k], distance,
                friction_of(objects[k]));
    }
    edge_distance_[i] = least;
    edge_motion_at_[i] = motion_m_;
    if (nearby.triangles.empty()) {
      far_pieces.push_back(i), far_middles.push_back(middle);
      nearby.reach = -1;
    }
  }
  // A piece is no nearer than its middle less half its length.
  refresh_distances(*scene_, far_middles, far_pieces, far_bound_m(), edge_distance_);
  for (std::size_t i : far_pieces)
    edge_distance_[i] -= 0.5 * (tool_edge_pieces_[i][1] - tool_edge_pieces_[i][0]).norm();
  for (const std::size_t i : due_) edge_queue_.push(edge_distance_[i] + edge_motion_at_[i], i);
}

// Every linearised distance the next step can change by more than its
// clearance: samples, tool edge pieces and scene vertices whose distance's lower bound is
// below `band`, against every triangle within the band.
void RigidProxyReference::collect_rows(double band) {
  rows_.clear();
  const Pose& pose = *proxy_;
  // Points with nothing within the band get their exact distance as their
  // bound (one batch per side), so they are not asked again for a while.
  std::vector<std::size_t> far_samples, far_vertices;
  std::vector<Vec3> far_points;
  sample_queue_.take(motion_m_ + band + kDueSlackM, due_);
  for (const std::size_t i : due_) {
    if (sample_distance_[i] - (motion_m_ - sample_motion_at_[i]) >= band) continue;
    const Vec3 p = pose.transform_point(tool_samples_[i]);
    scene_->triangles_within(p, band, near_);
    ++stats_.point_queries;
    double least = band;
    const std::vector<char> implied = implied_near_triangles(p);
    for (std::size_t k = 0; k < near_.size(); ++k) {
      const NearTriangle& t = near_[k];
      least = std::min(least, t.distance);
      if (t.distance > 0 && !implied[k])
        add_row((p - t.closest) / t.distance, t.closest, t.distance, friction_of(t.object));
    }
    sample_distance_[i] = least;
    sample_motion_at_[i] = motion_m_;
    if (near_.empty()) far_samples.push_back(i), far_points.push_back(p);
  }
  refresh_distances(*scene_, far_points, far_samples, far_bound_m(), sample_distance_);
  for (const std::size_t i : due_)
    sample_queue_.push(sample_distance_[i] + sample_motion_at_[i], i);
  collect_edge_rows(band);
  // Scene vertices in the cells the tool's sphere (grown by the band) touches.
  const double reach = tool_radius_m_ + band;
  const Vec3 low = ((pose.p.array() - reach) / cell_m_).floor();
  const Vec3 high = ((pose.p.array() + reach) / cell_m_).floor();
  for (int64_t x = static_cast<int64_t>(low.x()); x <= static_cast<int64_t>(high.x()); ++x)
    for (int64_t y = static_cast<int64_t>(low.y()); y <= static_cast<int64_t>(high.y()); ++y)
      for (int64_t z = static_cast<int64_t>(low.z()); z <= static_cast<int64_t>(high.z()); ++z) {
        const int64_t key = (x * 73856093) ^ (y * 19349663) ^ (z * 83492791);
        auto it = std::lower_bound(vertex_cells_.begin(), vertex_cells_.end(),
                                   std::pair<int64_t, int32_t>(key, -1));
        for (; it != vertex_cells_.end() && it->first == key; ++it) {
          const auto j = static_cast<std::size_t>(it->second);
          const Vec3& v = scene_vertices_[j];
          if ((v - pose.p).norm() > reach) continue;
          if (vertex_distance_[j] - (motion_m_ - vertex_motion_at_[j]) >= band) continue;
          tool_->triangles_within(pose.inverse_transform_point(v), band, near_);
          ++stats_.point_queries;
          double least = band;
          const std::vector<char> implied = implied_near_triangles(pose.inverse_transform_point(v));
          for (std::size_t k = 0; k < near_.size(); ++k) {
            const NearTriangle& t = near_[k];
            least = std::min(least, t.distance);
            const Vec3 closest = pose.transform_point(t.closest);
            if (t.distance > 0 && !implied[k])
              add_row((closest - v) / t.distance, closest, t.distance, scene_vertex_friction_[j]);
          }
          vertex_distance_[j] = least;
          vertex_motion_at_[j] = motion_m_;
          if (near_.empty()) far_vertices.push_back(j);
        }
      }
  far_points.clear();
  for (std::size_t j : far_vertices)
    far_points.push_back(pose.inverse_transform_point(scene_vertices_[j]));
  refresh_distances(*tool_, far_points, far_vertices, far_bound_m(), vertex_distance_);
}

// The step δ = (δx, φ) minimising ½(δ − g)ᵀK(δ − g) subject to every row
// a·δ ≥ b: with z = S(δ − g), S = K^½, a least-distance program min |z|
// subject to (a S⁻¹) z ≥ b − a·g, solved by NNLS (Lawson and Hanson,
// ch. 23). False when no step satisfies every row.
bool RigidProxyReference::least_distance_step(std::span<const Row> rows, const Vec6& g,
                                              Vec6& step) const {
  Vec6 s_inverse;
  s_inverse << Vec3::Constant(1 / std::sqrt(gains_.k_t)), Vec3::Constant(1 / std::sqrt(gains_.k_r));
  const auto m = static_cast<Eigen::Index>(rows.size());
  bool binding = false;
  for (const Row& row : rows) binding = binding || row.a.dot(g) < row.b;
  if (!binding) {
    step = g;
    return true;
  }
  MatX e(7, m);
  VecX f = VecX::Zero(7);
  f[6] = 1;
  for (Eigen::Index j = 0; j < m; ++j) {
    const Row& row = rows[static_cast<std::size_t>(j)];
    e.col(j).head<6>() = row.a.cwiseProduct(s_inverse);
    e(6, j) = row.b - row.a.dot(g);
  }
  const VecX u = non_negative_least_squares(e, f);
  const VecX r = e * u - f;
  if (!(std::abs(r[6]) > 1e-12)) return false;  // no step satisfies every row
  const Vec6 z = -r.head<6>() / r[6];
  step = g + z.cwiseProduct(s_inverse);
  return true;
}

bool RigidProxyReference::solve_step(const Vec3& gx, const Vec3& gphi, Vec6& step) const {
  Vec6 g;
  g << gx, gphi;
  return least_distance_step(rows_, g, step);
}

// The stick step: the rows `locked` (of friction_rows_) keep their tool
// points where they are along their faces (T δ = 0 for both tangents:
// rolling and pivoting about them stay free), every row of friction_rows_
// keeps its normal bound; exact, by the least-distance program, so that a
// contact the sweeps found sticking does not drift by their tolerance.
bool RigidProxyReference::stick_step(const Vec6& g, std::span<const std::size_t> locked,
                                     Vec6& step) {
  stick_rows_.clear();
  const auto add = [&](const Vec3& direction, const Vec3& lever, double bound) {
    Row row;
    row.a << direction, lever.cross(direction);
    row.b = bound;
    stick_rows_.push_back(row);
  };
  for (const FrictionalContactRow& row : friction_rows_) add(row.normal, row.lever, row.bound);
  for (std::size_t k : locked) {
    const FrictionalContactRow& row = friction_rows_[k];
    const Vec3 t1 = perpendicular_unit(row.normal), t2 = row.normal.cross(t1);
    for (const Vec3& t : {t1, t2}) add(t, row.lever, 0), add(-t, row.lever, 0);
  }
  return least_distance_step(stick_rows_, g, step);
}

double RigidProxyReference::frictionless_kkt_residual(const Vec3& gx, const Vec3& gphi) const {
  std::vector<const Row*> contacts;  // the rows within 10 ε
  for (const Row& row : rows_)
    if (row.distance <= 10 * settings_.clearance_m) contacts.push_back(&row);
  Vec6 pull;  // S g: the coupling's pull in the energy metric
  pull << std::sqrt(gains_.k_t) * gx, std::sqrt(gains_.k_r) * gphi;
  if (!(pull.norm() > 0)) return 0;
  if (contacts.empty()) return 1;
  MatX e(6, static_cast<Eigen::Index>(contacts.size()));
  for (std::size_t j = 0; j < contacts.size(); ++j) {
    const Vec6& a = contacts[j]->a;
    e.col(static_cast<Eigen::Index>(j)) << a.head<3>() / std::sqrt(gains_.k_t),
        a.tail<3>() / std::sqrt(gains_.k_r);
  }
  // Contact forces Aᵀλ balance the pull K g: in the metric, E λ = −S g.
  const VecX f = -pull;
  const VecX lambda = non_negative_least_squares(e, f);
  return (e * lambda - f).norm() / pull.norm();
}

// The frictional step: the quasi-static incremental problem with one
// Coulomb cone per row (Signorini, |f_t| ≤ μ f_n, maximal dissipation),
// solved by the constrained-contact Gauss–Seidel with its Alart–Curnier
// polish (frictional_contact_solver.h) with R = K⁻¹ and the pull g as the
// free motion; then finished exactly: the step nearest to its answer (in
// the energy's metric) that keeps every row, by solve_step, so no row is
// left violated by the sweeps' tolerance and no normal lift is added.
bool RigidProxyReference::solve_frictional_step(const Vec3& gx, const Vec3& gphi, Vec6& step) {
  Vec6 g;
  g << gx, gphi;
  bool binding = false;
  for (const Row& row : rows_) binding = binding || row.a.dot(g) < row.b;
  if (!binding) {  // nothing pushes: no contact force, no friction
    step = g;
    friction_ = {};
    return true;
  }
  // The rows the pull violates, and the contacts (within 10 ε); more while
  // the answer violates others.
  std::vector<char> taken(rows_.size(), 0);
  for (std::size_t i = 0; i < rows_.size(); ++i)
    taken[i] = rows_[i].a.dot(g) < rows_[i].b || rows_[i].distance <= 10 * settings_.clearance_m;
  std::vector<Vec3> forces;  // per row of friction_rows_: (λ, t1, t2), N
  Vec6 answer = g;
  for (int round = 0; round < kFrictionRounds; ++round) {
    select_friction_rows(taken);
    const FrictionalContactSolution& solution = sweep_friction(g);
    answer = solution.velocity;
    forces = solution.impulses;
    // Every loaded contact stuck (its tool point slid less than
    // kStickSlipM): the exact stick step instead of the sweeps' answer.
    std::vector<std::size_t> locked;
    bool stuck = true;
    for (std::size_t k = 0; k < friction_rows_.size() && stuck; ++k) {
      const FrictionalContactRow& row = friction_rows_[k];
      if (!(forces[k].x() > 0) || !(row.friction > 0)) continue;
      const Vec3 slip = answer.head<3>() + answer.tail<3>().cross(row.lever);
      stuck = (slip - row.normal.dot(slip) * row.normal).norm() <= kStickSlipM;
      locked.push_back(k);
    }
    Vec6 held;
    if (stuck && !locked.empty() && stick_step(g, locked, held)) answer = held;
    bool more = false;
    for (std::size_t i = 0; i < rows_.size(); ++i)
      if (!taken[i] && rows_[i].a.dot(answer) < rows_[i].b) taken[i] = more = true;
    if (!more) break;
  }
  record_friction(forces, answer, g);
  return solve_step(answer.head<3>(), answer.tail<3>(), step);
}

// Of the taken rows, the ones that carry what all do (contact_support.h),
// as friction_rows_: a face's hundreds of sample rows, or a sphere's cap of
// rows that cannot bind, would leave the sweeps creeping.
void RigidProxyReference::select_friction_rows(const std::vector<char>& taken) {
  std::vector<ContactRowGeometry> geometry;
  std::vector<std::size_t> taken_rows;
  for (std::size_t i = 0; i < rows_.size(); ++i)
    if (taken[i]) {
      const Row& row = rows_[i];
      geometry.push_back({row.point, row.a.head<3>(), row.b, row.friction});
      taken_rows.push_back(i);
    }
  friction_rows_.clear();
  for (std::size_t k : supporting_rows(geometry)) {
    const Row& row = rows_[taken_rows[k]];
    friction_rows_.push_back({row.a.head<3>(), row.point - proxy_->p, row.b, row.friction});
  }
}

// The sweeps over friction_rows_ with the coupling's compliance as the
// response and the pull g as the free motion, warm from the last solve's
// forces where it had the same rows (the next iteration of an update, or
// the next update at rest), so that they go on from where they stopped.
const FrictionalContactSolution& RigidProxyReference::sweep_friction(const Vec6& g) {
  Mat6 response = Mat6::Zero();
  response.diagonal() << Vec3::Constant(1 / gains_.k_t), Vec3::Constant(1 / gains_.k_r);
  bool same = warm_rows_.size() == friction_rows_.size();
  for (std::size_t k = 0; same && k < friction_rows_.size(); ++k)
    same = (warm_rows_[k].first - (friction_rows_[k].lever + proxy_->p)).norm() < 1e-9 &&
           (warm_rows_[k].second - friction_rows_[k].normal).norm() < 1e-9;
  const FrictionalContactSolution& solution =
      friction_solver_.solve(response, g, friction_rows_,
                             same ? std::span<const Vec3>(warm_forces_) : std::span<const Vec3>());
  warm_rows_.clear();
  for (const FrictionalContactRow& row : friction_rows_)
    warm_rows_.push_back({row.lever + proxy_->p, row.normal});
  warm_forces_ = solution.impulses;
  return solution;
}

// friction_ from the rows' forces and the step answered for the pull g.
void RigidProxyReference::record_friction(std::span<const Vec3> forces, const Vec6& answer,
                                          const Vec6& g) {
  friction_ = {};
  Vec3 normal_resultant = Vec3::Zero();
  for (std::size_t k = 0; k < friction_rows_.size(); ++k) {
    const FrictionalContactRow& row = friction_rows_[k];
    const Vec3& force = forces[k];
    if (!(force.x() > 0)) continue;
    friction_.limit_n += row.friction * force.x();
    normal_resultant += force.x() * row.normal;
    if (row.friction > 0) friction_.loaded.push_back({row.lever + proxy_->p, row.normal});
  }
  if (normal_resultant.norm() > 0) friction_.normal = normal_resultant.normalized();
  // The share of the pull the contact forces leave unbalanced: with
  // δ = g + K⁻¹ w, |S⁻¹ w + S g| / |S g| = |S δ| / |S g|.
  const Vec6 s =
      (Vec6() << Vec3::Constant(std::sqrt(gains_.k_t)), Vec3::Constant(std::sqrt(gains_.k_r)))
          .finished();
  friction_.residual = answer.cwiseProduct(s).norm() / g.cwiseProduct(s).norm();
  friction_.active = true;
}

bool RigidProxyReference::start_at(const Pose& device) {
  const auto clear = [&](const PointQueryResult& found, std::size_t i) {
    return !found.inside[i] && found.distance[i] >= settings_.clearance_m;
  };
  // The point that blocked the last start, alone first: a tool that stays
  // inside the scene costs one point a tick, not the whole sampling (a
  // tool started inside a mesh once cost 11 ms a tick).
  if (blocking_sample_ < tool_samples_.size()) {
    const Vec3 point = device.transform_point(tool_samples_[blocking_sample_]);
    PointQueryResult found_one;
    scene_->query_points(
        {.points = std::span<const Vec3>(&point, 1), .want_inside = true, .want_closest = true},
        found_one);
    if (!clear(found_one, 0)) return false;
  }
  std::vector<Vec3> points(tool_samples_.size());
  for (std::size_t i = 0; i < points.size(); ++i)
    points[i] = device.transform_point(tool_samples_[i]);
  // One query: every point outside the scene and at least ε from it.
  PointQueryResult found;
  scene_->query_points({.points = points, .want_inside = true, .want_closest = true}, found);
  for (std::size_t i = 0; i < points.size(); ++i)
    if (!clear(found, i)) {
      blocking_sample_ = i;
      return false;
    }
  proxy_ = device;
  return true;
}

std::optional<IdealRendering> RigidProxyReference::update(const Pose& device) {
  // The device where it was at a converged update (a hold): the proxy is
  // where that update left it, in equilibrium, and nothing slides.
  if (last_ && last_->device.p == device.p && last_->device.q.coeffs() == device.q.coeffs()) {
    stats_.iterations = 0;
    stats_.point_queries = 0;
    stats_.sticking = stats_.friction_limit_n > 0;
    return last_->rendering;
  }
  last_.reset();
  stats_ = RigidProxyUpdateStats{};
  if (!proxy_ && !start_at(device)) return std::nullopt;
  Pose& pose = *proxy_;
  const Pose start = pose;
  const double eps = settings_.clearance_m;
  const double rotation_limit = std::sqrt(eps / std::max(tool_radius_m_, 1e-9));
  Vec3 gx, gphi;
  Vec6 last_step = Vec6::Zero();  // (m, rad) the last iteration's step before scaling
  double damping = 1;             // halved at each frictional reversal
  for (;;) {
    gx = device.p - pose.p;
    gphi = rotation_vector(device.q * pose.q.conjugate());
    const double full = gx.norm() + gphi.norm() * tool_radius_m_;
    if (full <= settings_.step_tolerance_m) {
      rows_.clear();
      friction_ = {};
      stats_.converged = true;
      break;
    }
    if (stats_.iterations >= settings_.max_iterations) break;
    ++stats_.iterations;
    // The band follows the steps taken: wide enough for the last one twice
    // over, four times wider after a step it cut short. Steps in contact
    // are short, and a narrow band linearises few triangles.
    const double band =
        std::clamp(std::min(full, band_hint_m_), 4 * eps, settings_.band_max_m) + eps;
    collect_rows(band);
    stats_.constraints = static_cast<int>(rows_.size());
    friction_ = {};
    const bool frictional =
        settings_.friction &&
        std::any_of(rows_.begin(), rows_.end(), [](const Row& row) { return row.friction > 0; });
    Vec6 step;
    if (!(frictional ? solve_frictional_step(gx, gphi, step) : solve_step(gx, gphi, step))) {
      stats_.infeasible = true;
      break;
    }
    const Vec3 dx = step.head<3>();
    const Vec3 phi = step.tail<3>();
    const double moves = dx.norm() + phi.norm() * tool_radius_m_;
    // A frictional step that turns back on the last one (the contacts'
    // linearisations alternating between two sets, each sending the proxy
    // back toward the other) is halved, and so on at each reversal: the
    // alternation converges to the pose between them.
    if (frictional && last_step.dot(step) < -0.5 * last_step.norm() * step.norm()) damping *= 0.5;
    last_step = step;
    // The frictional sweeps' answer is good to a few nanometres where a
    // contact's normal and tangential forces are strongly coupled through
    // the tool's rotation (their error then drifts the proxy by that much
    // each iteration): a frictional update ends at ten times the tolerance.
    const double tolerance = frictional
                                 ? kFrictionalStepToleranceFactor * settings_.step_tolerance_m
                                 : settings_.step_tolerance_m;
    if (damping * moves <= tolerance) {
      stats_.converged = true;
      break;
    }
    double scale = std::min(1.0, (band - eps) / moves);
    band_hint_m_ = scale < 1 ? 4 * band : 2 * moves;
    if (!rows_.empty() && phi.norm() > rotation_limit)
      scale = std::min(scale, rotation_limit / phi.norm());
    scale *= damping;
    pose.p += scale * dx;
    pose.q = (quat_from_rotation_vector(scale * phi) * pose.q).normalized();
    motion_m_ += scale * moves;
  }
  IdealRendering rendering;
  rendering.proxy = pose;
  rendering.display.force = gains_.k_t * (pose.p - device.p);
  rendering.display.torque = -gains_.k_r * rotation_vector(device.q * pose.q.conjugate());
  for (const Row& row : rows_)
    rendering.in_contact = rendering.in_contact || row.distance <= 10 * eps;
  if (friction_.active) {
    stats_.kkt_residual = friction_.residual;
    stats_.friction_limit_n = friction_.limit_n;
    // Sticking: no loaded frictional contact's tool point slid along its
    // face over the update (rolling and pivoting do not slide).
    stats_.sticking = friction_.limit_n > 0;
    for (const auto& [point, normal] : friction_.loaded) {
      const Vec3 slip = point - start.transform_point(pose.inverse_transform_point(point));
      if ((slip - normal.dot(slip) * normal).norm() > kStickSlipM) stats_.sticking = false;
    }
    if (rendering.in_contact) rendering.contact_normal = friction_.normal;
  } else {
    stats_.kkt_residual = rows_.empty() ? 0.0 : frictionless_kkt_residual(gx, gphi);
    if (rendering.in_contact && rendering.display.force.norm() > 0)
      rendering.contact_normal = rendering.display.force.normalized();
  }
  if (stats_.converged) last_ = Held{device, rendering};
  return rendering;
}

}  // namespace hb
