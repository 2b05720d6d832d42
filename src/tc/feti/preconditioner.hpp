#pragma once
// The FETI dual preconditioners, apart from feti.hpp so that plain settings (the case file's
// physics::Problem) name them without PETSc.

namespace tc::feti {

enum class Preconditioner {
  none,
  lumped,     // Σ_s B_s A_s B_sᵀ
  dirichlet,  // Σ_s B_s S_s B_sᵀ, S_s the Schur complement of A_s on its interface dofs
};
[[nodiscard]] const char* name(Preconditioner p);

}  // namespace tc::feti
