// SPDX-License-Identifier: GPL-3.0-or-later
#include "render/camera.h"

#include "io/model/error.h"

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>

namespace dtf::render {

StandardView parseView(const std::string& n) {
  if (n == "superior") return StandardView::Superior;
  if (n == "inferior") return StandardView::Inferior;
  if (n == "anterior") return StandardView::Anterior;
  if (n == "posterior") return StandardView::Posterior;
  if (n == "left") return StandardView::Left;
  if (n == "right") return StandardView::Right;
  if (n == "axial") return StandardView::Axial;
  if (n == "coronal") return StandardView::Coronal;
  if (n == "sagittal") return StandardView::Sagittal;
  throw UsageError("unknown view '" + n +
                   "' (axial, coronal, sagittal, superior, inferior, anterior, posterior, left, right)");
}

const char* viewName(StandardView v) {
  switch (v) {
  case StandardView::Superior: return "superior";
  case StandardView::Inferior: return "inferior";
  case StandardView::Anterior: return "anterior";
  case StandardView::Posterior: return "posterior";
  case StandardView::Left: return "left";
  case StandardView::Right: return "right";
  case StandardView::Axial: return "axial";
  case StandardView::Coronal: return "coronal";
  case StandardView::Sagittal: return "sagittal";
  }
  return "?";
}

glm::dmat4 Camera::view() const { return glm::lookAt(eye, target, up); }

glm::dmat4 Camera::projection(double aspect) const {
  if (orthographic) {
    double h = orthoHalfHeight, w = h * aspect;
    return glm::ortho(-w, w, -h, h, nearPlane, farPlane);
  }
  return glm::perspective(glm::radians(fovYDeg), aspect, nearPlane, farPlane);
}

void Camera::lookAt(const glm::dvec3& e, const glm::dvec3& t, const glm::dvec3& u) {
  eye = e;
  target = t;
  // Keep up orthogonal to the viewing direction.
  glm::dvec3 f = glm::normalize(t - e);
  glm::dvec3 r = glm::cross(f, u);
  if (glm::length(r) < 1e-9) r = glm::cross(f, std::abs(f.z) < 0.9 ? glm::dvec3(0, 0, 1) : glm::dvec3(0, 1, 0));
  up = glm::normalize(glm::cross(glm::normalize(r), f));
}

void Camera::fit(const glm::dvec3& lo, const glm::dvec3& hi, double aspect, double margin) {
  glm::dvec3 c = 0.5 * (lo + hi);
  double radius = std::max(0.5 * glm::length(hi - lo), 1e-6);
  glm::dvec3 f = forward(), r = right(), u = glm::cross(r, f);
  // Extent of the box's corners across the image.
  double ex = 0, ey = 0;
  for (int i = 0; i < 8; ++i) {
    glm::dvec3 p((i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z);
    ex = std::max(ex, std::abs(glm::dot(p - c, r)));
    ey = std::max(ey, std::abs(glm::dot(p - c, u)));
  }
  double halfH = std::max(ey, ex / std::max(aspect, 1e-6)) * margin;
  double dist;
  if (orthographic) {
    orthoHalfHeight = halfH;
    dist = 2.0 * radius + 1.0;
  } else {
    dist = halfH / std::tan(0.5 * glm::radians(fovYDeg)) + radius;
  }
  target = c;
  eye = c - f * dist;
  nearPlane = std::max(dist - 1.5 * radius, orthographic ? 0.1 : 0.01 * dist);
  farPlane = dist + 1.5 * radius;
}

glm::dmat3 arcballRotation(const glm::dvec2& from, const glm::dvec2& to) {
  auto onSphere = [](glm::dvec2 p) {
    double d2 = glm::dot(p, p);
    if (d2 <= 1.0) return glm::dvec3(p, std::sqrt(1.0 - d2));
    return glm::dvec3(p / std::sqrt(d2), 0.0);
  };
  glm::dvec3 a = onSphere(from), b = onSphere(to);
  glm::dvec3 axis = glm::cross(a, b);
  double s = glm::length(axis), c = std::clamp(glm::dot(a, b), -1.0, 1.0);
  if (s < 1e-12) return glm::dmat3(1.0);
  double angle = std::atan2(s, c);
  return glm::dmat3(glm::rotate(glm::dmat4(1.0), angle, axis / s));
}

void Camera::trackball(const glm::dvec2& from, const glm::dvec2& to) {
  // The arcball rotation is in eye coordinates; rotating the object by R equals rotating the camera by
  // R^-1 about the target.
  glm::dmat3 rEye = arcballRotation(from, to);
  glm::dvec3 f = forward(), r = right(), u = glm::cross(r, f);
  glm::dmat3 eyeToWorld(r, u, -f);
  glm::dmat3 rWorld = eyeToWorld * glm::transpose(rEye) * glm::transpose(eyeToWorld);
  glm::dvec3 offset = eye - target;
  eye = target + rWorld * offset;
  up = glm::normalize(rWorld * u);
}

void Camera::zoom(double factor) {
  if (orthographic) {
    orthoHalfHeight *= factor;
  } else {
    eye = target + (eye - target) * factor;
  }
}

Camera Camera::standard(StandardView v, const glm::dvec3& lo, const glm::dvec3& hi, double aspect,
                        bool neurological, bool ortho) {
  if (v == StandardView::Axial) v = neurological ? StandardView::Superior : StandardView::Inferior;
  if (v == StandardView::Coronal) v = neurological ? StandardView::Posterior : StandardView::Anterior;
  if (v == StandardView::Sagittal) v = neurological ? StandardView::Right : StandardView::Left;
  glm::dvec3 dir, upDir; // dir: from target towards the camera
  switch (v) {
  case StandardView::Superior: dir = {0, 0, 1}, upDir = {0, 1, 0}; break;
  case StandardView::Inferior: dir = {0, 0, -1}, upDir = {0, 1, 0}; break;
  case StandardView::Anterior: dir = {0, 1, 0}, upDir = {0, 0, 1}; break;
  case StandardView::Posterior: dir = {0, -1, 0}, upDir = {0, 0, 1}; break;
  case StandardView::Left: dir = {-1, 0, 0}, upDir = {0, 0, 1}; break;
  default: dir = {1, 0, 0}, upDir = {0, 0, 1}; break;
  }
  Camera cam;
  cam.orthographic = ortho;
  glm::dvec3 c = 0.5 * (lo + hi);
  cam.lookAt(c + dir * 100.0, c, upDir);
  cam.fit(lo, hi, aspect);
  return cam;
}

} // namespace dtf::render
