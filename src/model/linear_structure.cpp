#include "model/linear_structure.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace slidespec::model {

LinearStructure flat_structure(const Parameters& p) {
  const int n = p.N + 1;
  using Triplet = Eigen::Triplet<double>;
  std::vector<Triplet> mass, damping, stiffness;
  mass.emplace_back(0, 0, p.M);
  damping.emplace_back(0, 0, p.N * p.m * p.eta0);
  stiffness.emplace_back(0, 0, p.N * p.k0);
  for (int i = 1; i < n; ++i) {
    mass.emplace_back(i, i, p.m);
    // Viscoelastic spring to the block: k0 and m*eta0 act on the difference.
    damping.emplace_back(0, i, -p.m * p.eta0);
    damping.emplace_back(i, 0, -p.m * p.eta0);
    damping.emplace_back(i, i, p.m * (p.eta0 + p.eta1));
    stiffness.emplace_back(0, i, -p.k0);
    stiffness.emplace_back(i, 0, -p.k0);
    stiffness.emplace_back(i, i, p.k0);
  }
  // Chain springs k1 between neighbours; the ring closes N -> 1.
  auto link = [&](int i, int j) {
    stiffness.emplace_back(i, i, p.k1);
    stiffness.emplace_back(j, j, p.k1);
    stiffness.emplace_back(i, j, -p.k1);
    stiffness.emplace_back(j, i, -p.k1);
  };
  for (int i = 1; i + 1 < n; ++i) link(i, i + 1);
  if (p.chain == ChainEnds::ring) link(n - 1, 1);

  LinearStructure s;
  s.mass.resize(n, n);
  s.damping.resize(n, n);
  s.stiffness.resize(n, n);
  s.mass.setFromTriplets(mass.begin(), mass.end());
  s.damping.setFromTriplets(damping.begin(), damping.end());
  s.stiffness.setFromTriplets(stiffness.begin(), stiffness.end());
  for (int i = 1; i < n; ++i) s.contacts.push_back({i, p.random_force_variance(), p.a});
  return s;
}

LumpedStructure lump(const LinearStructure& structure, const std::vector<int>& class_of) {
  const int n = structure.coordinates();
  if (static_cast<int>(class_of.size()) != n || class_of[0] != 0)
    throw std::invalid_argument("lump: class_of must cover every coordinate, block in class 0");
  int classes = 0;
  for (int c : class_of) classes = std::max(classes, c + 1);
  for (int i = 1; i < n; ++i)
    if (class_of[i] == 0) throw std::invalid_argument("lump: the block must be a class of its own");

  Eigen::MatrixXd P = Eigen::MatrixXd::Zero(n, classes);
  for (int i = 0; i < n; ++i) P(i, class_of[i]) = 1.0;
  const Eigen::MatrixXd counts = P.transpose() * P;

  LumpedStructure out;
  auto reduce = [&](const Eigen::SparseMatrix<double>& full, const char* name) {
    const Eigen::MatrixXd FP = full * P;
    const Eigen::MatrixXd quotient = counts.inverse() * (P.transpose() * FP);
    // Equitable: F P = P Q, i.e. each row's class sums depend only on the row's class.
    const double residual = (FP - P * quotient).cwiseAbs().maxCoeff();
    const double scale = FP.cwiseAbs().maxCoeff();
    if (residual > 1e-12 * scale)
      throw std::invalid_argument(std::string("lump: partition is not equitable for ") + name);
    return Eigen::MatrixXd(P.transpose() * FP);
  };
  // In class-mean coordinates q = P y, P^T M P y'' + ... = P^T F: sums of the class rows.
  out.mass = reduce(structure.mass, "mass");
  out.damping = reduce(structure.damping, "damping");
  out.stiffness = reduce(structure.stiffness, "stiffness");
  for (const Contact& c : structure.contacts) out.class_of_contact.push_back(class_of[c.coordinate]);
  return out;
}

LumpedStructure lumped_flat_structure(const Parameters& p) {
  std::vector<int> class_of(p.N + 1, 1);
  class_of[0] = 0;
  return lump(flat_structure(p), class_of);
}

}  // namespace slidespec::model
