// SPDX-License-Identifier: GPL-3.0-or-later
// The positions of a Polylines (io/model/geometry.h): one contiguous array of points, either owned (a
// std::vector) or viewed in place in memory that an owner keeps alive, such as a memory-mapped TRX file
// (io/formats/trx.h), so a whole-brain tractogram of GBs is opened without a copy. Reading is the same either
// way (data(), operator[], iteration over plain pointers, std::span). The first change to a viewed array
// (any non-const access) copies it into memory first, so a mapped file is never written and a Polylines stays
// a value type: copies of a viewed array share the view. Const access never copies, so threads may read one
// array together.
#pragma once

#include <algorithm>
#include <cstddef>
#include <glm/glm.hpp>
#include <initializer_list>
#include <memory>
#include <utility>
#include <vector>

namespace dtf {

class PointArray {
public:
  using value_type = glm::vec3;
  using size_type = std::size_t;
  using difference_type = std::ptrdiff_t;
  using reference = glm::vec3&;
  using const_reference = const glm::vec3&;
  using pointer = glm::vec3*;
  using const_pointer = const glm::vec3*;
  using iterator = glm::vec3*;
  using const_iterator = const glm::vec3*;

  PointArray() = default;
  PointArray(std::vector<glm::vec3> points) : owned_(std::move(points)) {} // NOLINT: a vector is a PointArray
  PointArray(std::initializer_list<glm::vec3> points) : owned_(points) {}
  template <typename It> PointArray(It first, It last) : owned_(first, last) {}
  // A view of n points at `data`, which `owner` keeps valid for as long as any copy of the array lives.
  static PointArray view(std::shared_ptr<const void> owner, const glm::vec3* data, size_type n) {
    PointArray a;
    a.owner_ = std::move(owner);
    a.view_ = data;
    a.viewSize_ = n;
    return a;
  }
  // Whether the points are viewed in place (no copy of them is held).
  bool viewed() const { return owner_ != nullptr; }

  size_type size() const { return owner_ ? viewSize_ : owned_.size(); }
  bool empty() const { return size() == 0; }
  size_type capacity() const { return owner_ ? viewSize_ : owned_.capacity(); }
  const glm::vec3* data() const { return owner_ ? view_ : owned_.data(); }
  const glm::vec3& operator[](size_type i) const { return data()[i]; }
  const_iterator begin() const { return data(); }
  const_iterator end() const { return data() + size(); }
  const_iterator cbegin() const { return begin(); }
  const_iterator cend() const { return end(); }
  const glm::vec3& front() const { return *begin(); }
  const glm::vec3& back() const { return end()[-1]; }
  // An owned copy of the points.
  std::vector<glm::vec3> toVector() const { return std::vector<glm::vec3>(begin(), end()); }
  // The points as a vector, moved out (copied from a view); the array is left empty.
  std::vector<glm::vec3> take() {
    std::vector<glm::vec3> v = std::move(own());
    owned_.clear();
    return v;
  }

  // Non-const access: a viewed array is copied into memory first.
  glm::vec3* data() { return own().data(); }
  glm::vec3& operator[](size_type i) { return own()[i]; }
  iterator begin() { return own().data(); }
  iterator end() { return own().data() + owned_.size(); }
  glm::vec3& front() { return own().front(); }
  glm::vec3& back() { return own().back(); }

  void reserve(size_type n) { own().reserve(n); }
  void resize(size_type n) { own().resize(n); }
  void resize(size_type n, const glm::vec3& v) { own().resize(n, v); }
  void clear() {
    release();
    owned_.clear();
  }
  void shrink_to_fit() { own().shrink_to_fit(); }
  void push_back(const glm::vec3& p) { own().push_back(p); }
  template <typename... A> glm::vec3& emplace_back(A&&... a) { return own().emplace_back(std::forward<A>(a)...); }
  void pop_back() { own().pop_back(); }
  void assign(size_type n, const glm::vec3& v) {
    release();
    owned_.assign(n, v);
  }
  template <typename It> void assign(It first, It last) {
    std::vector<glm::vec3> v(first, last); // the source may be this array's own view
    release();
    owned_ = std::move(v);
  }
  template <typename It> iterator insert(const_iterator at, It first, It last) {
    const auto k = at - std::as_const(*this).begin(); // before a view is copied
    const auto it = own().insert(owned_.begin() + k, first, last);
    return owned_.data() + (it - owned_.begin());
  }
  iterator insert(const_iterator at, const glm::vec3& p) {
    const auto k = at - std::as_const(*this).begin();
    const auto it = own().insert(owned_.begin() + k, p);
    return owned_.data() + (it - owned_.begin());
  }
  iterator erase(const_iterator first, const_iterator last) {
    const auto a = first - std::as_const(*this).begin(), b = last - std::as_const(*this).begin();
    const auto it = own().erase(owned_.begin() + a, owned_.begin() + b);
    return owned_.data() + (it - owned_.begin());
  }
  void swap(PointArray& o) noexcept {
    owned_.swap(o.owned_);
    owner_.swap(o.owner_);
    std::swap(view_, o.view_);
    std::swap(viewSize_, o.viewSize_);
  }

  friend bool operator==(const PointArray& a, const PointArray& b) {
    return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin());
  }

private:
  // The owned vector, after copying a view into it.
  std::vector<glm::vec3>& own() {
    if (owner_) {
      owned_.assign(view_, view_ + viewSize_);
      release();
    }
    return owned_;
  }
  void release() {
    owner_.reset();
    view_ = nullptr;
    viewSize_ = 0;
  }

  std::vector<glm::vec3> owned_;
  std::shared_ptr<const void> owner_; // set: the points are viewed at view_
  const glm::vec3* view_ = nullptr;
  size_type viewSize_ = 0;
};

} // namespace dtf
