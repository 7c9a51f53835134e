#pragma once
// Stage 5's dense product (K*^-1 P*) AI, pluggable so it can run on the device
// when the block is large (3|s| x 3|I| doubles read every frame: bandwidth-bound).
#include <Eigen/Core>
#include <string>

namespace softcut::hybrid {

class NonoperationalProduct {
 public:
  virtual ~NonoperationalProduct() = default;
  virtual std::string name() const = 0;
  // out = (K*^-1 P*) AI: AI (3|I|) m, out (3|s|) m, resized.
  virtual void apply(const Eigen::VectorXd& AI, Eigen::VectorXd& out) = 0;
};

}  // namespace softcut::hybrid
