#include "core/verify/matrix_bounds.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <vector>

namespace linkscape::verify {
namespace {

using Eigen::Index;
using Eigen::MatrixXd;
using Eigen::VectorXd;
using IntervalMatrix = std::vector<std::vector<Interval>>;

// Whether every symmetric matrix in the enclosure is positive definite: its
// Cholesky factorisation in interval arithmetic meets only positive pivots
// (each pivot's enclosure holds the pivot of every member).
bool certainly_positive_definite(const IntervalMatrix& B) {
  const std::size_t n = B.size();
  IntervalMatrix L(n, std::vector<Interval>(n, Interval(0.0)));
  for (std::size_t j = 0; j < n; ++j) {
    Interval pivot = B[j][j];
    for (std::size_t k = 0; k < j; ++k) pivot -= sqr(L[j][k]);
    if (!(pivot.lo > 0)) return false;
    L[j][j] = sqrt(pivot);
    for (std::size_t i = j + 1; i < n; ++i) {
      Interval sum = B[i][j];
      for (std::size_t k = 0; k < j; ++k) sum -= L[i][k] * L[j][k];
      L[i][j] = sum / L[j][j];
    }
  }
  return true;
}

// |A^T u| / |u|, enclosed: a singular value of A is at least (for the
// largest) or at most (for the smallest) it.
Interval rayleigh(const MatrixXd& A, const VectorXd& u) {
  Interval top(0.0), bottom(0.0);
  for (Index j = 0; j < A.cols(); ++j) {
    Interval entry(0.0);
    for (Index i = 0; i < A.rows(); ++i) entry += Interval(A(i, j)) * Interval(u(i));
    top += sqr(entry);
  }
  for (Index i = 0; i < u.size(); ++i) bottom += sqr(Interval(u(i)));
  return sqrt(top / bottom);
}

}  // namespace

SpectrumBounds spectrum_bounds(const MatrixXd& A_given) {
  // The wide side's Gram matrix A A^T: its eigenvalues are the squared singular values.
  const MatrixXd A = A_given.rows() <= A_given.cols() ? A_given : MatrixXd(A_given.transpose());
  const Index n = A.rows();
  const std::size_t size = std::size_t(n);
  IntervalMatrix G(size, std::vector<Interval>(size));
  MatrixXd G_mid(n, n);
  for (Index i = 0; i < n; ++i)
    for (Index j = 0; j < n; ++j) {
      Interval sum(0.0);
      for (Index k = 0; k < A.cols(); ++k) sum += Interval(A(i, k)) * Interval(A(j, k));
      G[std::size_t(i)][std::size_t(j)] = sum;
      G_mid(i, j) = sum.mid();
    }
  const Eigen::SelfAdjointEigenSolver<MatrixXd> eig(G_mid);
  if (eig.info() != Eigen::Success) return {};
  const VectorXd& values = eig.eigenvalues();  // ascending
  auto shifted = [&](double shift, double sign) {
    IntervalMatrix B = G;
    for (std::size_t i = 0; i < B.size(); ++i)
      for (std::size_t j = 0; j < B.size(); ++j)
        B[i][j] = Interval(sign) * G[i][j] - (i == j ? Interval(sign * shift) : Interval(0.0));
    return B;
  };
  SpectrumBounds b;
  // mu I - G positive definite: every eigenvalue below mu; G - nu I: above nu.
  // Each shift relative to the eigenvalue and, for the rounding of G's
  // entries (about n eps |G|), absolute: first tight, then looser.
  const double rounding = double(n) * 0x1p-52 * G_mid.cwiseAbs().maxCoeff();
  for (double slack : {1e-9, 1e-6, 1e-3}) {
    const double mu = values(n - 1) * (1 + slack) + 1e3 * slack * rounding + kTiny;
    if (certainly_positive_definite(shifted(mu, -1.0))) {
      b.largest_upper = up(std::sqrt(up(mu)));
      break;
    }
  }
  for (double slack : {1e-9, 1e-6, 1e-3}) {
    const double nu = values(0) * (1 - slack) - 1e3 * slack * rounding;
    if (nu > 0 && certainly_positive_definite(shifted(nu, 1.0))) {
      b.smallest_lower = down(std::sqrt(down(nu)));
      break;
    }
  }
  b.largest_lower = std::max(0.0, rayleigh(A, eig.eigenvectors().col(n - 1)).lo);
  b.smallest_upper = rayleigh(A, eig.eigenvectors().col(0)).hi;
  return b;
}

double spectral_norm_bound(const MatrixXd& magnitude) {
  Interval frobenius(0.0);
  double rows = 0, cols = 0;
  for (Index i = 0; i < magnitude.rows(); ++i) {
    Interval row(0.0);
    for (Index j = 0; j < magnitude.cols(); ++j) {
      frobenius += sqr(Interval(magnitude(i, j)));
      row += Interval(magnitude(i, j));
    }
    rows = std::max(rows, row.hi);
  }
  for (Index j = 0; j < magnitude.cols(); ++j) {
    Interval col(0.0);
    for (Index i = 0; i < magnitude.rows(); ++i) col += Interval(magnitude(i, j));
    cols = std::max(cols, col.hi);
  }
  return std::min(sqrt(frobenius).hi, sqrt(Interval(rows) * Interval(cols)).hi);
}

double inverse_residual_bound(const MatrixXd& A, const MatrixXd& X) {
  MatrixXd magnitude(A.rows(), X.cols());
  for (Index i = 0; i < A.rows(); ++i)
    for (Index j = 0; j < X.cols(); ++j) {
      Interval sum(i == j ? 1.0 : 0.0);
      for (Index k = 0; k < A.cols(); ++k) sum -= Interval(A(i, k)) * Interval(X(k, j));
      magnitude(i, j) = sum.mag();
    }
  return spectral_norm_bound(magnitude);
}

}  // namespace linkscape::verify
