#pragma once
// Search stage of the mortar pair (Tribol's "search"): a bounding-volume hierarchy of axis-
// aligned boxes over the master faces. Built top-down by median splits along the longest axis
// of the box centres, so the tree has depth ⌈log₂(n/leaf)⌉; a query visits O(log n + hits)
// nodes, and the search for all slave faces costs O(n log n).
#include <array>
#include <vector>

#include "tc/contact/geometry.hpp"

namespace tc::contact {

struct Aabb {
  Vec3 lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
  void grow(const Vec3& p);
  void merge(const Aabb& b);
  [[nodiscard]] Aabb inflated(double r) const;
  [[nodiscard]] Aabb inflated(const Vec3& r) const;  // by r[i] along axis i
  /// Boxes that touch or overlap (closed boxes).
  [[nodiscard]] bool overlaps(const Aabb& b) const;
  [[nodiscard]] double diagonal() const { return norm(hi - lo); }
};

[[nodiscard]] Aabb bounding_box(const FacetPoints& f);

/// Axis-aligned bounding-box tree over a fixed set of boxes (the master faces of one update).
class AabbTree {
 public:
  explicit AabbTree(std::vector<Aabb> boxes);
  /// Appends to `hits` the indices of the boxes that overlap `box` (in no particular order).
  void query(const Aabb& box, std::vector<int>& hits) const;
  [[nodiscard]] int size() const { return static_cast<int>(boxes_.size()); }

 private:
  static constexpr int leaf_size = 4;
  struct Node {
    Aabb box;
    int left = -1, right = -1;  // children, or -1 for a leaf
    int begin = 0, end = 0;     // items_[begin, end) of a leaf
  };
  int build(int begin, int end, const std::vector<Vec3>& centres);

  std::vector<Aabb> boxes_;
  std::vector<int> items_;  // box indices, permuted so that each node owns a range
  std::vector<Node> nodes_;
};

}  // namespace tc::contact
