#include "model/linear_structure.hpp"

#include <cmath>
#include <mutex>
#include <stdexcept>
#include <string>
#include <utility>

namespace slidespec::model {

namespace {

/// The entries of M, D and K as they are emitted; duplicates are summed in emission order.
struct Entries {
  std::vector<Eigen::Triplet<double>> mass, damping, stiffness;

  /// A chain spring k1 between neighbours i and j.
  void link(int i, int j, double k1) {
    stiffness.emplace_back(i, i, k1);
    stiffness.emplace_back(j, j, k1);
    stiffness.emplace_back(i, j, -k1);
    stiffness.emplace_back(j, i, -k1);
  }

  LinearStructure assemble(int n) const {
    LinearStructure s;
    s.mass.resize(n, n);
    s.damping.resize(n, n);
    s.stiffness.resize(n, n);
    s.mass.setFromTriplets(mass.begin(), mass.end());
    s.damping.setFromTriplets(damping.begin(), damping.end());
    s.stiffness.setFromTriplets(stiffness.begin(), stiffness.end());
    return s;
  }
};

}  // namespace

std::vector<int> level_of_coordinates(const Parameters& p) {
  std::vector<int> level_of = {0};
  for (int l = 1; l <= p.levels; ++l) level_of.insert(level_of.end(), static_cast<std::size_t>(p.blocks(l)), l);
  return level_of;
}

LinearStructure tree_structure(const Parameters& p) {
  // Entries are emitted level by level (block, then each level's blocks, then its chain
  // links); duplicates are summed in that order.
  const std::vector<int> level_of = level_of_coordinates(p);
  const int n = static_cast<int>(level_of.size());
  Entries entries;
  auto& [mass, damping, stiffness] = entries;
  const Level first = p.level(1);
  mass.emplace_back(0, 0, p.M);
  damping.emplace_back(0, 0, first.N * first.m * first.eta0);
  stiffness.emplace_back(0, 0, first.N * first.k0);
  // drive = spring: the load point moves at v, so in the comoving coordinate its spring is a
  // restoring force -k_drive xi on the big block alone (docs/model.md §9).
  if (p.drive == Drive::spring) stiffness.emplace_back(0, 0, p.k_drive);
  int level_start = 1;  // first coordinate of the current level
  for (int l = 1; l <= p.levels; ++l) {
    const Level level = p.level(l);
    const int count = static_cast<int>(p.blocks(l));
    const int parent_start = l == 1 ? 0 : level_start - static_cast<int>(p.blocks(l - 1));
    const double substrate = p.touches(l) ? p.eta1 : 0.0;
    for (int b = 0; b < count; ++b) {
      const int i = level_start + b, parent = l == 1 ? 0 : parent_start + b / level.N;
      mass.emplace_back(i, i, level.m);
      // Viscoelastic spring to the parent: k0 and m*eta0 act on the difference.
      damping.emplace_back(parent, i, -level.m * level.eta0);
      damping.emplace_back(i, parent, -level.m * level.eta0);
      damping.emplace_back(i, i, level.m * (level.eta0 + substrate));
      stiffness.emplace_back(parent, i, -level.k0);
      stiffness.emplace_back(i, parent, -level.k0);
      stiffness.emplace_back(i, i, level.k0);
      if (l < p.levels) {  // the springs to its own children, as the block's are to level 1
        const Level below = p.level(l + 1);
        damping.emplace_back(i, i, below.N * below.m * below.eta0);
        stiffness.emplace_back(i, i, below.N * below.k0);
      }
    }
    // Chain springs k1 between neighbouring siblings; a ring closes the last to the first.
    for (int family = level_start; family < level_start + count; family += level.N) {
      for (int i = family; i + 1 < family + level.N; ++i) entries.link(i, i + 1, level.k1);
      if (level.chain == ChainEnds::ring) entries.link(family + level.N - 1, family, level.k1);
    }
    level_start += count;
  }

  LinearStructure s = entries.assemble(n);
  const double f_kin = p.friction_per_miniblock();
  for (int i = 1; i < n; ++i) {
    const int l = level_of[static_cast<std::size_t>(i)];
    if (p.touches(l)) s.contacts.push_back({i, p.random_force_variance(l), p.level(l).a, p.level(l).alpha * f_kin});
  }
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
  out.contacts = structure.contacts;
  return out;
}

LumpedStructure lumped_tree_structure(const Parameters& p) {
  // describe() names every parameter exactly (it is what makes two runs the same run).
  static std::mutex kept_mutex;
  static std::vector<std::pair<std::string, std::string>> kept_key;
  static LumpedStructure kept;
  auto key = describe(p);
  // Built under the lock: the threads of a run all ask at once, and one build serves them.
  const std::lock_guard<std::mutex> lock(kept_mutex);
  if (key != kept_key) {
    kept = lump(tree_structure(p), level_of_coordinates(p));
    kept_key = std::move(key);
  }
  return kept;
}

}  // namespace slidespec::model
