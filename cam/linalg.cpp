#include "cam/linalg.hpp"

#include <Eigen/Eigenvalues>
#include <unsupported/Eigen/MatrixFunctions>

namespace polarcam::linalg {

Eigen::MatrixXd expm(const Eigen::MatrixXd& m) { return m.exp(); }

Eigen::VectorXcd eigenvalues(const Eigen::MatrixXd& m) {
  return Eigen::EigenSolver<Eigen::MatrixXd>(m, false).eigenvalues();
}

}  // namespace polarcam::linalg
