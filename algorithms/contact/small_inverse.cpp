#include "algorithms/contact/small_inverse.h"

namespace hb {

Mat6 lower_triangular_inverse(const Mat6& lower) {
  Mat6 inverse = Mat6::Zero();
  for (int j = 0; j < 6; ++j) {
    inverse(j, j) = 1 / lower(j, j);
    for (int i = j + 1; i < 6; ++i) {
      double sum = 0;
      for (int k = j; k < i; ++k) sum += lower(i, k) * inverse(k, j);
      inverse(i, j) = -sum / lower(i, i);
    }
  }
  return inverse;
}

}  // namespace hb
