// The quasi-static spectrum of docs/model.md §7.5: the force process seen in time, with
// generator v u(G) L, solved without expansion in eps. Each contact's uniform force is
// replaced by Gauss-Legendre nodes; the symmetric functions of the N forces live on the
// multisets of nodes, where the time-weighted generator is symmetric, and its resolvent's
// spectral measure seen from G is found by Lanczos (a Gauss quadrature of that measure).
#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <vector>

#include <Eigen/Dense>

#include "slidespec/theory.hpp"
#include "theory/quadrature.hpp"

namespace slidespec {

namespace {

// Gauss-Legendre nodes and weights on [-1, 1], weights summing to 1 (a uniform law's).
void uniform_nodes(int n, std::vector<double>& x, std::vector<double>& w) {
  theory_detail::gauss_legendre_rule(n, x, w);
  for (double& weight : w) weight /= 2;
}

// Multisets of `size` items over `types` kinds.
double multiset_count(int size, int types) {
  if (types == 0) return size == 0 ? 1 : 0;
  double c = 1;  // C(size + types - 1, types - 1)
  for (int k = 1; k < types; ++k) c = c * (size + k) / k;
  return c;
}

/// The multisets of N contacts' forces over n nodes (counts per node, most of node 0 first),
/// flattened, and their ranks.
struct Multisets {
  Multisets(int contacts, int nodes) : N(contacts), n(nodes), table(N + 1, std::vector<double>(n + 1)) {
    for (int m = 0; m <= N; ++m)
      for (int k = 0; k <= n; ++k) table[m][k] = multiset_count(m, k);
    states = static_cast<std::size_t>(table[N][n]);
    counts.resize(states * n);
    std::vector<int> c(n, 0);
    std::size_t index = 0;
    // Recursive enumeration by an explicit odometer: c_0 from N down, then the rest.
    const auto fill = [&](auto&& self, int type, int left) -> void {
      if (type == n - 1) {
        c[type] = left;
        std::copy(c.begin(), c.end(), counts.begin() + static_cast<std::ptrdiff_t>(index * n));
        ++index;
        return;
      }
      for (int k = left; k >= 0; --k) {
        c[type] = k;
        self(self, type + 1, left - k);
      }
    };
    fill(fill, 0, N);
  }
  /// The index of the multiset with counts c.
  std::size_t rank(const int* c) const {
    double r = 0;
    int left = N;
    for (int t = 0; t < n - 1; ++t) {
      for (int k = c[t] + 1; k <= left; ++k) r += table[left - k][n - t - 1];
      left -= c[t];
    }
    return static_cast<std::size_t>(r);
  }

  int N, n;
  std::vector<std::vector<double>> table;  // multiset_count(m, k)
  std::size_t states = 0;
  std::vector<int> counts;
};

/// The symmetrised time-weighted generator A = u^(1/2) P^(1/2) L P^(-1/2) u^(1/2) (rates per a
/// of distance) in compressed rows, its diagonal apart: a contact's force renewed from node k
/// to node m.
struct Generator {
  Generator(const Multisets& sets, const std::vector<double>& u, const std::vector<double>& w)
      : diagonal(sets.states), row_start(sets.states + 1, 0) {
    const int n = sets.n;
    std::vector<int> d(n);
    for (std::size_t i = 0; i < sets.states; ++i) {
      const int* c = &sets.counts[i * n];
      double out = 0;
      for (int k = 0; k < n; ++k) {
        if (c[k] == 0) continue;
        out += c[k] * (1 - w[k]);
        for (int m = 0; m < n; ++m) {
          if (m == k) continue;
          std::copy(c, c + n, d.begin());
          --d[k];
          ++d[m];
          const std::size_t j = sets.rank(d.data());
          column.push_back(j);
          value.push_back(std::sqrt(u[i] * u[j] * c[k] * w[m] * (c[m] + 1) * w[k]));
        }
      }
      diagonal[i] = -u[i] * out;
      row_start[i + 1] = column.size();
    }
  }
  std::vector<double> diagonal;
  std::vector<std::size_t> row_start, column;
  std::vector<double> value;
};

/// Lanczos with full reorthogonalisation from q: K steps give a K-point Gauss rule for the
/// spectral measure of A seen from q, exact for resolvents to high order in 1/z. Returns the
/// tridiagonal matrix.
Eigen::MatrixXd lanczos(const Generator& A, const Eigen::VectorXd& q) {
  const auto states = static_cast<std::size_t>(q.size());
  const int steps = static_cast<int>(std::min<std::size_t>(states, 60));
  Eigen::MatrixXd basis(states, steps);
  std::vector<double> alpha, beta;
  Eigen::VectorXd v = q / std::sqrt(q.squaredNorm()), next(states);
  for (int k = 0; k < steps; ++k) {
    basis.col(k) = v;
    for (std::size_t i = 0; i < states; ++i) {
      double s = A.diagonal[i] * v[i];
      for (std::size_t e = A.row_start[i]; e < A.row_start[i + 1]; ++e) s += A.value[e] * v[A.column[e]];
      next[i] = s;
    }
    const double a = v.dot(next);
    alpha.push_back(a);
    for (int pass = 0; pass < 2; ++pass) next -= basis.leftCols(k + 1) * (basis.leftCols(k + 1).transpose() * next);
    const double b = next.norm();
    if (k + 1 == steps || b < 1e-13 * std::sqrt(std::fabs(a) + 1)) break;
    beta.push_back(b);
    v = next / b;
  }
  const int K = static_cast<int>(alpha.size());
  Eigen::MatrixXd T = Eigen::MatrixXd::Zero(K, K);
  for (int k = 0; k < K; ++k) {
    T(k, k) = alpha[k];
    if (k + 1 < K) T(k, k + 1) = T(k + 1, k) = beta[k];
  }
  return T;
}

}  // namespace

struct QuasiStaticTheory::Impl {
  LumpedTheory first_order;
  double first_weight = 0;             // S = N s2 / Delta^2: Phi_1 = S / (z + 1), z in units of v/a
  double rate = 1;                     // v/a [1/s]
  std::vector<double> nodes, weights;  // Lanczos: Phi(z) = sum weights / (z - nodes)
  int contacts = 0, force_nodes = 0;
  double inverse_speed = 1;  // <1/u> over distance

  explicit Impl(const Parameters& p) : first_order(p) {
    if (p.drive == Drive::spring)
      throw InputError("the quasi-static spectrum is derived for a constant drive force (docs/model.md §7.5)");
    if (p.renewal != Renewal::poisson)
      throw InputError("renewal: the quasi-static spectrum is computed for poisson renewal (docs/model.md §7.5)");
    const Landmarks l = landmarks(p);
    if (l.forces_can_stall)
      throw InputError(
          "alpha F_kin >= 2 (F_drive - F_kin): the forces can stall the block, which has no spectrum (docs/model.md "
          "§8)");
    const int level = theory_detail::single_touching_level(p, "the quasi-static spectrum");
    contacts = static_cast<int>(p.blocks(level));
    rate = p.renewal_rate(level);
    const double delta = p.F_drive - p.F_kin;
    const double s2 = p.random_force_variance(level) / (delta * delta);  // in units of Delta^2
    const double half_width = std::sqrt(3 * s2);                         // a force's range is +-half_width Delta
    first_weight = contacts * s2;
    // As many nodes per force as keep the multisets few (20 000 states); 24 at most, 2 at least.
    int n = 2;
    while (n < 24 && multiset_count(contacts, n + 1) <= 20000) ++n;
    force_nodes = n;
    solve(half_width, n);
  }

  void solve(double half_width, int n) {
    std::vector<double> x, w;
    uniform_nodes(n, x, w);
    for (double& xi : x) xi *= half_width;
    const int N = contacts;
    const Multisets sets(N, n);
    const std::size_t states = sets.states;
    // Per state: the speed u, the force G, the distance law pi.
    std::vector<double> u(states), G(states), pi(states);
    std::vector<double> lgamma_count(N + 2);
    for (int k = 0; k <= N + 1; ++k) lgamma_count[k] = std::lgamma(k + 1.0);
    for (std::size_t i = 0; i < states; ++i) {
      const int* c = &sets.counts[i * n];
      double g = 0, log_pi = lgamma_count[N];
      for (int k = 0; k < n; ++k) {
        g += c[k] * x[k];
        log_pi += c[k] * std::log(w[k]) - lgamma_count[c[k]];
      }
      G[i] = g;
      u[i] = 1 - g;
      pi[i] = std::exp(log_pi);
    }
    const Generator A(sets, u, w);
    double mean_inverse = 0, mean_G = 0;
    for (std::size_t i = 0; i < states; ++i) mean_inverse += pi[i] / u[i], mean_G += pi[i] * G[i] / u[i];
    inverse_speed = mean_inverse;
    mean_G /= mean_inverse;  // <G> in time
    Eigen::VectorXd q(states);
    for (std::size_t i = 0; i < states; ++i) q[i] = std::sqrt(pi[i] / u[i]) * (G[i] - mean_G);
    const double norm2 = q.squaredNorm();
    const Eigen::MatrixXd T = lanczos(A, q);
    const int K = static_cast<int>(T.rows());
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(T);
    double largest = 0;
    for (int k = 0; k < K; ++k) largest = std::max(largest, std::fabs(eigen.eigenvalues()[k]));
    for (int k = 0; k < K; ++k) {
      const double theta = eigen.eigenvalues()[k], weight = norm2 * std::pow(eigen.eigenvectors()(0, k), 2);
      if (std::fabs(theta) <= 1e-10 * largest) continue;  // the stationary direction (q has none of it)
      nodes.push_back(theta);
      weights.push_back(weight / mean_inverse);
    }
  }

  // Re Phi(-i omega) / Re Phi_1(-i omega).
  double ratio(double omega) const {
    const std::complex<double> z(0, -omega / rate);
    std::complex<double> phi = 0;
    for (std::size_t k = 0; k < nodes.size(); ++k) phi += weights[k] / (z - nodes[k]);
    return phi.real() / (first_weight / (z + 1.0)).real();
  }
};

QuasiStaticTheory::QuasiStaticTheory(const Parameters& p) : impl_(std::make_shared<const Impl>(p)) {}

double QuasiStaticTheory::operator()(double omega) const { return impl_->first_order(omega) * ratio(omega); }

double QuasiStaticTheory::ratio(double omega) const { return impl_->ratio(std::fabs(omega)); }

int QuasiStaticTheory::force_nodes() const { return impl_->force_nodes; }

BeyondFirstOrder theory_beyond_first_order(const Parameters& p) {
  SecondOrderTheory series(p);  // first: it refuses what neither covers
  if (best_theory(p).kind == TheoryKind::quasi_static) return {QuasiStaticTheory(p), true};
  return {series, false};
}

}  // namespace slidespec
