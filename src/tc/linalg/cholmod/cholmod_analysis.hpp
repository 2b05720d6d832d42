#pragma once
// CHOLMOD's symbolic analysis alone (cholmod_analyze on a pattern): the size of the factor a
// body's direct solve would make and the flops of making it, in a fraction of the
// factorisation's time, for io::auto_subdomains' choice between the direct and the FETI path.
#include <vector>

namespace tc::linalg {

/// What cholmod_analyze predicts for a factor: exact for the pattern it is given, since the
/// ordering and the supernodes depend on the pattern alone (CholmodFactor analyses the
/// same lower triangle with the same defaults).
struct FactorAnalysis {
  double n = 0;           // rows
  double entries = 0;     // nonzeros of L (CHOLMOD's lnz)
  double flops = 0;       // of the numeric factorisation (CHOLMOD's fl)
  double bytes = 0;       // the factor's storage: its values (supernodal: L->xsize) and indices
  double work_bytes = 0;  // the largest update block cholmod_factorize allocates (maxcsize)
};

/// Analyses the symmetric pattern given by its upper triangle row by row (the CSR entries
/// c ≥ r of each row r, sorted: what CholmodFactor hands CHOLMOD as the lower triangle of the
/// columns). `start` has rows + 1 entries.
[[nodiscard]] FactorAnalysis analyse_cholesky(const std::vector<int>& start,
                                              const std::vector<int>& column);

}  // namespace tc::linalg
