// The model's linear structure: mass, damping and stiffness about the steady sliding state.
//
// Everything downstream (exact theory, stepper) works from this description, not from
// the chain itself, so that other contact geometries (docs/model.md §6: blocks on
// blocks) only need to build another LinearStructure.
#pragma once

#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <vector>

#include "slidespec/parameters.hpp"

namespace slidespec::model {

/// A coordinate that touches the substrate: it feels -(f_kin + f_j) with f_j renewed
/// every renewal distance.
struct Contact {
  int coordinate;                ///< index into the coordinates (0 is the big block)
  double random_force_variance;  ///< s2 = alpha^2 f_kin^2 / 12 [N^2]
  double renewal_distance;       ///< a [m]
  /// alpha f_kin [N]: the force is uniform on [-1/2, 1/2) times this (s2 = amplitude^2 / 12,
  /// kept separately because the two are rounded from alpha and f_kin in different orders).
  double random_force_amplitude;
};

/// M q'' + D q' + K q = (random forces on the contacts), for the fluctuation q of the
/// coordinates about their steady sliding motion. Coordinate 0 is the big block, so
/// q_0 = xi. Stiffness annihilates a common translation (all springs are relative) except
/// with drive = spring, where K_00 also holds k_drive (the load point's spring).
struct LinearStructure {
  Eigen::SparseMatrix<double> mass;
  Eigen::SparseMatrix<double> damping;
  Eigen::SparseMatrix<double> stiffness;
  std::vector<Contact> contacts;

  int coordinates() const { return static_cast<int>(mass.rows()); }
};

/// Blocks on blocks (docs/model.md §6): the big block, then every level's blocks in
/// order, each block's children consecutive and chained to each other; the touching
/// levels' blocks are the contacts. One level is the flat model of docs/model.md §1.
LinearStructure tree_structure(const Parameters& p);

/// Level of each coordinate of tree_structure(p) (0 for the big block): an equitable
/// partition, since all blocks of a level see the same springs to parent, children and
/// siblings' sums.
std::vector<int> level_of_coordinates(const Parameters& p);

/// The same structure in class-mean coordinates of an equitable partition (coordinates
/// in one class are interchangeable: every row of M, D, K sums the same over each class).
/// The block is a class of its own, so xi is exact; the random forces enter as class sums.
struct LumpedStructure {
  Eigen::MatrixXd mass;       ///< P^T M P
  Eigen::MatrixXd damping;    ///< P^T D P
  Eigen::MatrixXd stiffness;  ///< P^T K P
  /// class_of_contact[j]: which lumped coordinate contact j's force is added to.
  std::vector<int> class_of_contact;
  std::vector<Contact> contacts;  ///< the full structure's contacts, whose forces the classes sum
};

/// Lumps `structure` over `class_of` (class 0 must be the block alone); throws
/// std::invalid_argument if the partition is not equitable.
LumpedStructure lump(const LinearStructure& structure, const std::vector<int>& class_of);

/// The tree lumped by level: levels + 1 coordinates whatever the number of blocks; input
/// class l carries the forces of level l (the flat model's lumping for one level).
/// The last parameter set's is kept: with a million blocks the full tree takes about half a
/// second to build, and a run asks for it per batch and several times over for its result,
/// where a signal waits for it.
LumpedStructure lumped_tree_structure(const Parameters& p);

}  // namespace slidespec::model
