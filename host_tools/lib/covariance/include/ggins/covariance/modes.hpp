// Eigenstructure of the reduced error dynamics (F without the bias states) and
// the modal split of the covariance. Welker et al., section VI (end): with
// gravity gradiometry the reduced dynamics matrix has the eigenvalues
// +-sqrt(2) w_s and +-j w_s (w_s the Schuler frequency); the 6x6 F of eq. (9)
// adds a double zero (the position errors integrate the velocity errors).
#pragma once

#include <complex>
#include <vector>

#include "ggins/covariance/model.hpp"

namespace ggins::covariance {

using cd = std::complex<double>;

// Eigenvalues of F sorted by real part, then imaginary part (descending).
std::vector<cd> sorted_eigenvalues(const MatrixXd& F);

// Spectral projector onto the eigenvector of F with the largest real part
// (the unstable mode): Pi = v w^T with F v = l v, w^T F = l w^T, w^T v = 1.
// Pi is unique (independent of eigenvector scaling). Returns l in *lambda.
MatrixXd unstable_projector(const MatrixXd& F, double* lambda);

}  // namespace ggins::covariance
