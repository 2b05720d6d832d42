#include "tc/linalg/compliance.hpp"

#include <fmt/format.h>

#include <algorithm>

#include "tc/core/error.hpp"
#include "tc/core/numeric/threads.hpp"
#include "tc/core/verify.hpp"
#include "tc/linalg/cholesky_solver.hpp"
#include "tc/linalg/dense.hpp"

namespace tc::linalg {

Compliance::Compliance(PetscInt n_dofs, int ranks, int rank)
    : ranks_(ranks), rank_(rank), index_(static_cast<size_t>(n_dofs), -1) {}

Compliance::~Compliance() = default;

PetscInt Compliance::missing(std::span<const PetscInt> dofs) const {
  std::vector<PetscInt> fresh;
  for (const PetscInt d : dofs)
    if (index_[d] < 0) fresh.push_back(d);
  std::sort(fresh.begin(), fresh.end());
  return static_cast<PetscInt>(std::unique(fresh.begin(), fresh.end()) - fresh.begin());
}

bool Compliance::on_t(const core::Vector& w, double scale, std::vector<double>& wt) const {
  wt.resize(dofs_.size());
  const auto wv = w.read();
  const auto n = static_cast<PetscInt>(index_.size());
  for (PetscInt i = 0; i < n; ++i)
    if (wv[i] != 0.0 && index_[i] < 0) return false;
  for (size_t q = 0; q < dofs_.size(); ++q) wt[q] = scale * wv[dofs_[q]];
  return true;
}

bool Compliance::apply(const core::Vector&, core::Vector&) const {
  return false;
}

bool Compliance::begin_corrected(const core::Vector&, core::Vector&, CorrectedSolve&) const {
  return false;
}

bool Compliance::finish_corrected(CorrectedSolve&, const core::Vector&, core::Vector&) const {
  return false;
}

void Compliance::store_block(Eigen::Index first, Eigen::Index k, Eigen::Index old,
                             const double* part) {
  const auto t = static_cast<Eigen::Index>(dofs_.size());
  store(first, k, old, [&](Eigen::Index a, Eigen::Index c) { return part[a + c * t]; });
}

PetscInt Compliance::cover(std::span<const PetscInt> dofs) {
  const auto old = static_cast<Eigen::Index>(dofs_.size());
  for (const PetscInt d : dofs)
    if (index_[d] < 0) {
      index_[d] = static_cast<PetscInt>(dofs_.size());
      dofs_.push_back(d);
    }
  const auto t = static_cast<Eigen::Index>(dofs_.size());
  if (t == old) return 0;
  // A solve per new column, ~4 nnz(L) flops each, nnz(L) some tens of n for a 3D body: the
  // level-3 solves of many columns are a kernel that gains from threads (core/numeric/threads.hpp).
  const core::KernelThreads threads(40.0 * static_cast<double>(index_.size()) *
                                    static_cast<double>(t - old));
  chunks_.push_back(static_cast<PetscInt>(t - old));
  const auto old_rows = static_cast<Eigen::Index>(rows_.size());
  for (Eigen::Index q = old; q < t; ++q)
    if (q % ranks_ == rank_) rows_.push_back(static_cast<PetscInt>(q));
  const auto n_rows = static_cast<Eigen::Index>(rows_.size());
  s_.conservativeResize(n_rows, t);
  s_.bottomRows(n_rows - old_rows).setZero();
  s_.rightCols(t - old).setZero();
  grow(old);
  return static_cast<PetscInt>(t - old);
}

void Compliance::replay(std::span<const PetscInt> dofs, std::span<const PetscInt> chunks) {
  if (std::equal(dofs.begin(), dofs.end(), dofs_.begin(), dofs_.end()) &&
      std::equal(chunks.begin(), chunks.end(), chunks_.begin(), chunks_.end()))
    return;  // already this record (a restore into the run that wrote it)
  for (const PetscInt d : dofs_) index_[d] = -1;
  dofs_.clear();
  chunks_.clear();
  rows_.clear();
  s_.resize(0, 0);
  size_t at = 0;
  for (const PetscInt k : chunks) {
    if (at + static_cast<size_t>(k) > dofs.size()) throw Error("compliance: bad replay record");
    cover(dofs.subspan(at, static_cast<size_t>(k)));
    at += static_cast<size_t>(k);
  }
}

void save_compliances(std::span<const std::unique_ptr<Compliance>> compliances,
                      std::vector<std::vector<int>>& record) {
  for (const auto& c : compliances) {
    record.emplace_back(c->dofs().begin(), c->dofs().end());
    record.emplace_back(c->chunks().begin(), c->chunks().end());
  }
}

void replay_compliances(std::span<const std::unique_ptr<Compliance>> compliances,
                        std::span<const std::vector<int>> record, const char* owner) {
  if (record.size() != 2 * compliances.size())
    throw Error(
        fmt::format("checkpoint: the {} compliance record does not match the bodies", owner));
  for (size_t i = 0; i < compliances.size(); ++i) {
    for (const int d : record[2 * i])
      if (d < 0 || d >= compliances[i]->n_dofs())
        throw Error(fmt::format("checkpoint: a {} compliance dof out of range", owner));
    compliances[i]->replay(
        std::vector<PetscInt>(record[2 * i].begin(), record[2 * i].end()),
        std::vector<PetscInt>(record[2 * i + 1].begin(), record[2 * i + 1].end()));
  }
}

BlockCompliance::BlockCompliance(PetscInt n_dofs, BlockSolve solve_many, std::string path)
    : Compliance(n_dofs), solve_many_(std::move(solve_many)), path_(std::move(path)) {}

void BlockCompliance::grow(Eigen::Index old) {
  constexpr Eigen::Index block = 64;  // bounds the dense work space to n × block
  const Eigen::Index t = size();
  for (Eigen::Index j0 = old; j0 < t; j0 += block) solve_block(j0, std::min(block, t - j0), old);
}

void BlockCompliance::solve_block(Eigen::Index first, Eigen::Index k, Eigen::Index old) {
  const PetscInt n = n_dofs();
  dense::Dense rhs = dense::zero_dense(n, k), sol = dense::zero_dense(n, k);
  {
    PetscScalar* r = nullptr;
    TC_PETSC(MatDenseGetArray(rhs.get(), &r));
    PetscInt ld = n;
    TC_PETSC(MatDenseGetLDA(rhs.get(), &ld));
    for (Eigen::Index c = 0; c < k; ++c) r[c * ld + dofs()[first + c]] = 1.0;
    TC_PETSC(MatDenseRestoreArray(rhs.get(), &r));
  }
  dense::assemble(rhs.get());
  dense::assemble(sol.get());
  solve_many_(rhs.get(), sol.get());
  const PetscScalar* x = nullptr;
  TC_PETSC(MatDenseGetArrayRead(sol.get(), &x));
  PetscInt ld = n;
  TC_PETSC(MatDenseGetLDA(sol.get(), &ld));
  store(first, k, old, [&](Eigen::Index a, Eigen::Index c) { return x[c * ld + dofs()[a]]; });
  TC_PETSC(MatDenseRestoreArrayRead(sol.get(), &x));
}

std::vector<std::string> compliance_paths() {
  std::vector<std::string> out{"cholmod-supernodal (restricted solves)",
                               "cholmod-supernodal (forward solves)"};
  const auto packages = available_cholesky_packages();
  if (std::find(packages.begin(), packages.end(), MATSOLVERMUMPS) != packages.end())
    out.emplace_back("mumps selected inverse");
  out.emplace_back("block solves");
  out.emplace_back("feti");
  return out;
}

}  // namespace tc::linalg
