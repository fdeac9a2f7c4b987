// Dense matrix functions compiled once: Eigen's matrix exponential and its eigenvalue solver take many seconds to
// compile in every unit that instantiates them, so the units that need them (the drives' zero-order holds, the
// characteristic roots of the process models) call these instead.
#pragma once

#include <Eigen/Core>

namespace polarcam::linalg {

// exp(M) of a square matrix (Eigen's scaling and squaring with Pade approximants).
Eigen::MatrixXd expm(const Eigen::MatrixXd& m);

// The eigenvalues of a square matrix (Eigen's EigenSolver, without the eigenvectors), in its order.
Eigen::VectorXcd eigenvalues(const Eigen::MatrixXd& m);

}  // namespace polarcam::linalg
