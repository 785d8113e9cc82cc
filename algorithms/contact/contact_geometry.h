// The scene and the tool as a constrained-contact proxy sees them (the
// god-object's and constrained dynamics'), built once per renderer: the
// mesh CCD structures of the tool against the scene, with the tool in the
// frame at its centre of mass (the tool frame's axes) or, for a point tool,
// the point at its frame's origin; the tool's frames; the scene objects'
// Coulomb friction; and the escape of a start pose that is not free.
#pragma once

#include <span>
#include <vector>

#include "algorithms/ccd/mesh_ccd.h"
#include "algorithms/contact/contact_settings.h"
#include "algorithms/contact/proxy_motion.h"
#include "hapticbench/pose.h"
#include "hapticbench/scene.h"

namespace hb {

/// Where a start pose that is not free of the scene is moved.
struct StartEscape {
  Pose pose;              ///< tool frame, world: free of the scene (the start when it was)
  double distance_m = 0;  ///< how far the tool was moved, m
  /// The start touched the scene and was moved (a start within the
  /// standoff but touching nothing is free, and kept).
  bool escaped = false;
};

class ContactGeometry {
 public:
  /// tool: its mesh (tool frame, m) and centre of mass; scene: the static
  /// objects, each mesh placed by its pose, with its "friction". Of the
  /// settings (read_contact_settings), point_tool says what the tool is,
  /// and escape() uses the standoff and the CCD's settings. Builds the CCD
  /// structures or reads them from the disk cache (MeshCcd; throws
  /// InputError for an empty tool or a non-finite coordinate).
  ContactGeometry(const Tool& tool, std::span<const SceneObject> scene,
                  const ContactSettings& settings);

  /// The nearest free pose to the tool-frame pose `start` along 26
  /// directions (the faces, edges and corners of a cube, world frame; gaps
  /// of up to 27.6° between them, so a way out up to 12.8 % longer than the
  /// shortest straight one),
  /// orientation kept: for each, the tool is brought back from outside the
  /// scene's bounding sphere toward `start` and stopped by the mesh CCD
  /// `standoff` short of its first contact. A path that reaches `start`
  /// proves it free (returned unchanged); otherwise the shortest way out
  /// wins. A start that is free but enclosed, with every path from outside
  /// blocked, would be moved out too.
  StartEscape escape(const Pose& start) const;

  /// The CCD structures: the tool, in its centre-of-mass frame, against the
  /// scene (also for the build report).
  const MeshCcd& ccd() const { return ccd_; }
  /// The tool frame and the centre-of-mass frame the CCD sees the tool in.
  const ProxyFrames& frames() const { return frames_; }
  /// The tool's centre of mass in tool coordinates (m); zero for a point tool.
  const Vec3& centre_of_mass() const { return frames_.centre_of_mass; }
  /// Coulomb μ per scene object (the scene's "friction"), in MeshCcd's order.
  const std::vector<double>& friction() const { return friction_; }

 private:
  ContactSettings settings_;
  ProxyFrames frames_;
  MeshCcd ccd_;
  std::vector<double> friction_;  ///< Coulomb μ per scene object
};

}  // namespace hb
