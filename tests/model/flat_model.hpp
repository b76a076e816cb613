// The flat model's matrices written out from docs/model.md §1, §4 and §9,
// dense and independently of the library's assembler (src/model), for tests to check it.
#pragma once

#include <Eigen/Dense>
#include <complex>
#include <vector>

#include "slidespec/parameters.hpp"

namespace slidespec::as_written {

/// M q'' + D q' + K q = forces, q = (xi, miniblock offsets from their mean places).
struct FlatModel {
  Eigen::MatrixXd mass, damping, stiffness;
};

inline FlatModel flat_model(const Parameters& p) {
  const int n = p.N + 1;
  FlatModel f{Eigen::MatrixXd::Zero(n, n), Eigen::MatrixXd::Zero(n, n), Eigen::MatrixXd::Zero(n, n)};
  f.mass(0, 0) = p.M;
  f.damping(0, 0) = p.N * p.m * p.eta0;
  f.stiffness(0, 0) = p.N * p.k0;
  for (int i = 1; i < n; ++i) {
    f.mass(i, i) = p.m;
    f.damping(0, i) = f.damping(i, 0) = -p.m * p.eta0;
    f.damping(i, i) = p.m * (p.eta0 + p.eta1);
    f.stiffness(0, i) = f.stiffness(i, 0) = -p.k0;
    f.stiffness(i, i) = p.k0;
  }
  // Chain springs between neighbours; the ring closes N -> 1.
  auto link = [&](int i, int j) {
    f.stiffness(i, i) += p.k1;
    f.stiffness(j, j) += p.k1;
    f.stiffness(i, j) -= p.k1;
    f.stiffness(j, i) -= p.k1;
  };
  for (int i = 1; i + 1 < n; ++i) link(i, i + 1);
  if (p.chain == ChainEnds::ring) link(n - 1, 1);
  // The load point's spring pulls the block alone: -k_drive xi in comoving coordinates.
  if (p.drive == Drive::spring) f.stiffness(0, 0) += p.k_drive;
  return f;
}

/// One miniblock's random-force spectrum S_f [N^2 s] (docs/model.md §4), written out.
inline double force_spectrum(const Parameters& p, double omega) {
  const double f_kin = p.F_kin / p.N, s2 = p.alpha * p.alpha * f_kin * f_kin / 12, lambda = p.v / p.a;
  if (p.renewal == Renewal::poisson) return s2 * lambda / (M_PI * (lambda * lambda + omega * omega));
  const double T = p.a / p.v, half = omega * T / 2;
  const double sinc = half == 0 ? 1.0 : std::sin(half) / half;
  return s2 * T / (2 * M_PI) * sinc * sinc;
}

/// C_x(omega) = S_f sum_i |G_0i|^2, G = (K - omega^2 M - i omega D)^-1, by a dense LU.
inline double flat_model_spectrum(const Parameters& p, double omega) {
  const FlatModel f = flat_model(p);
  const Eigen::MatrixXcd Z = f.stiffness.cast<std::complex<double>>() -
                             omega * omega * f.mass.cast<std::complex<double>>() -
                             std::complex<double>(0, omega) * f.damping.cast<std::complex<double>>();
  const Eigen::MatrixXcd G = Z.fullPivLu().inverse();
  double sum = 0;
  for (int i = 1; i <= p.N; ++i) sum += std::norm(G(0, i));
  return force_spectrum(p, omega) * sum;
}

}  // namespace slidespec::as_written
