#pragma once
// Camera placement: automatic framing of the model or an explicit eye/target,
// and the OpenGL view and projection matrices.
#include <Eigen/Core>
#include <vector>

namespace softcut::render {

struct CameraSettings {
  // true: look at the centre of the rest shape from the orbit angles, just far
  // enough that all of it is in view (stable while the tissue deforms).
  // false: use eye and target as given.
  bool auto_frame = true;
  double azimuth_deg = -60.0;   // orbit angle about `up`, 0 = along the first axis normal to up
  double elevation_deg = 25.0;  // above the plane normal to `up`, in (-90, 90)
  double margin = 1.25;  // slack for deformation: the rest shape spans 1 / margin of the tighter side
  Eigen::Vector3d eye{1.0, -2.0, 1.0};  // m, used when !auto_frame
  Eigen::Vector3d target{0.0, 0.0, 0.0};  // m, used when !auto_frame
  Eigen::Vector3d up{0.0, 0.0, 1.0};
  double fov_y_deg = 30.0;  // vertical field of view, in (0, 180)
};

struct Camera {
  Eigen::Vector3d eye, target, up;  // m; up is orthonormalised against the view direction
  double fov_y_deg = 30.0, aspect = 1.0;
  double near = 0.01, far = 100.0;  // m, tight around the scene's content
  Eigen::Matrix4d view;             // world -> eye (OpenGL convention, looking down -z)
  Eigen::Matrix4d projection;       // eye -> clip

  // World point -> normalised device coordinates (x, y in [-1, 1] on screen, z depth).
  Eigen::Vector3d to_ndc(const Eigen::Vector3d& p) const;
};

// The camera for `settings`. auto_frame: looks at the centre of the bounding
// box of `frame` (the rest-shape surface nodes, m) from the orbit angles, at
// the nearest distance that keeps every point of `frame` inside the image
// shrunk by `margin`. Near/far are fitted to `frame` and the points of
// `extent` (what else is drawn; may be empty).
Camera resolve_camera(const CameraSettings& settings, int width, int height, const std::vector<Eigen::Vector3d>& frame,
                      const std::vector<const std::vector<Eigen::Vector3f>*>& extent);

}  // namespace softcut::render
