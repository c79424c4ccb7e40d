// SPDX-License-Identifier: GPL-3.0-or-later
// The viewer's camera: view and projection matrices in world RAS mm, look-at, trackball rotation, fitting
// to a bounding box, and the standard anatomical views. Every pass takes its matrices from here.
//
// View conventions (world RAS: +x = patient's right, +y = anterior, +z = superior):
//   superior  camera above, looking down, anterior up: patient's right on the image RIGHT
//   inferior  camera below, looking up, anterior up: patient's right on the image LEFT
//   anterior  camera in front, looking back, superior up: patient's right on the image LEFT
//   posterior camera behind, looking forward, superior up: patient's right on the image RIGHT
//   left      camera at the patient's left, looking right, superior up: anterior on the image LEFT
//   right     camera at the patient's right, looking left, superior up: anterior on the image RIGHT
// Display views follow the radiological convention by default (patient's right on the image left):
//   axial = inferior, coronal = anterior, sagittal = left (anterior on the image left).
// The neurological convention mirrors them: axial = superior, coronal = posterior, sagittal = right.
#pragma once

#include <glm/glm.hpp>

#include <string>

namespace dtf::render {

enum class StandardView { Superior, Inferior, Anterior, Posterior, Left, Right, Axial, Coronal, Sagittal };

// Parses superior|inferior|anterior|posterior|left|right|axial|coronal|sagittal; throws UsageError.
StandardView parseView(const std::string& name);
const char* viewName(StandardView v);

class Camera {
public:
  glm::dvec3 eye{0, 0, 100};
  glm::dvec3 target{0, 0, 0};
  glm::dvec3 up{0, 1, 0};
  bool orthographic = true;
  double fovYDeg = 30;          // perspective: vertical field of view
  double orthoHalfHeight = 100; // orthographic: half the visible height in mm
  double nearPlane = 1, farPlane = 1000;

  // World -> eye transform (right-handed, looking down -z).
  glm::dmat4 view() const;
  // Eye -> clip transform for a viewport of aspect width/height.
  glm::dmat4 projection(double aspect) const;
  glm::dvec3 forward() const { return glm::normalize(target - eye); }
  // Image-right direction in world space.
  glm::dvec3 right() const { return glm::normalize(glm::cross(forward(), up)); }

  void lookAt(const glm::dvec3& eyePos, const glm::dvec3& targetPos, const glm::dvec3& upDir);
  // Places the camera on its current viewing direction so the box [lo, hi] fills the viewport with the
  // given margin (1 = touching), and sets the clip planes around it.
  void fit(const glm::dvec3& lo, const glm::dvec3& hi, double aspect, double margin = 1.05);
  // Trackball (Shoemake arcball): rotates the camera about the target by the rotation that carries the
  // point `from` onto `to`, both in normalised viewport coordinates [-1, 1] (y up).
  void trackball(const glm::dvec2& from, const glm::dvec2& to);
  // Multiplies the visible size by `factor` (< 1 zooms in).
  void zoom(double factor);

  // A standard view of the box: direction and up from the table in the header comment, then fit().
  static Camera standard(StandardView v, const glm::dvec3& lo, const glm::dvec3& hi, double aspect,
                         bool neurological = false, bool orthographic = true);
};

// The arcball rotation (unit quaternion as angle-axis matrix) taking `from` to `to` on the unit sphere
// over the viewport; exposed for tests.
glm::dmat3 arcballRotation(const glm::dvec2& from, const glm::dvec2& to);

} // namespace dtf::render
