#include "tc/contact/search.hpp"

#include <algorithm>
#include <numeric>

namespace tc::contact {

void Aabb::grow(const Vec3& p) {
  for (int i = 0; i < 3; ++i) {
    lo[i] = std::min(lo[i], p[i]);
    hi[i] = std::max(hi[i], p[i]);
  }
}

void Aabb::merge(const Aabb& b) {
  grow(b.lo);
  grow(b.hi);
}

Aabb Aabb::inflated(double r) const {
  return inflated(Vec3{r, r, r});
}

Aabb Aabb::inflated(const Vec3& r) const {
  Aabb b = *this;
  for (int i = 0; i < 3; ++i) {
    b.lo[i] -= r[i];
    b.hi[i] += r[i];
  }
  return b;
}

bool Aabb::overlaps(const Aabb& b) const {
  for (int i = 0; i < 3; ++i)
    if (lo[i] > b.hi[i] || b.lo[i] > hi[i]) return false;
  return true;
}

Aabb bounding_box(const FacetPoints& f) {
  Aabb b;
  for (int a = 0; a < f.n; ++a) b.grow(f.x[a]);
  return b;
}

AabbTree::AabbTree(std::vector<Aabb> boxes) : boxes_(std::move(boxes)) {
  if (boxes_.empty()) return;
  items_.resize(boxes_.size());
  std::iota(items_.begin(), items_.end(), 0);
  std::vector<Vec3> centres(boxes_.size());
  for (size_t i = 0; i < boxes_.size(); ++i) centres[i] = 0.5 * (boxes_[i].lo + boxes_[i].hi);
  nodes_.reserve(2 * boxes_.size() / leaf_size + 2);
  build(0, static_cast<int>(boxes_.size()), centres);
}

int AabbTree::build(int begin, int end, const std::vector<Vec3>& centres) {
  const int id = static_cast<int>(nodes_.size());
  nodes_.emplace_back();
  Aabb box, spread;  // the node's box, and the box of its items' centres
  for (int i = begin; i < end; ++i) {
    box.merge(boxes_[items_[i]]);
    spread.grow(centres[items_[i]]);
  }
  nodes_[id].box = box;
  if (end - begin <= leaf_size) {
    nodes_[id].begin = begin;
    nodes_[id].end = end;
    return id;
  }
  const Vec3 extent = spread.hi - spread.lo;
  const int axis =
      static_cast<int>(std::max_element(extent.begin(), extent.end()) - extent.begin());
  const int mid = (begin + end) / 2;
  std::nth_element(items_.begin() + begin, items_.begin() + mid, items_.begin() + end,
                   [&](int a, int b) { return centres[a][axis] < centres[b][axis]; });
  const int left = build(begin, mid, centres);
  const int right = build(mid, end, centres);
  nodes_[id].left = left;  // nodes_ may have grown: index, do not hold references
  nodes_[id].right = right;
  return id;
}

void AabbTree::query(const Aabb& box, std::vector<int>& hits) const {
  if (nodes_.empty()) return;
  int stack[128];  // depth ≤ log₂(n) + 1 ≪ 128 for any mesh that fits in memory
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& node = nodes_[stack[--top]];
    if (!node.box.overlaps(box)) continue;
    if (node.left < 0) {
      for (int i = node.begin; i < node.end; ++i)
        if (boxes_[items_[i]].overlaps(box)) hits.push_back(items_[i]);
    } else {
      stack[top++] = node.left;
      stack[top++] = node.right;
    }
  }
}

}  // namespace tc::contact
