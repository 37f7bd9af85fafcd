#include "animanifold/perturbation.hpp"

#include <cstring>
#include <sstream>

namespace animanifold {

namespace {

// SplitMix64's finaliser: a bijection of 64-bit words that mixes every input
// bit into every output bit.
std::uint64_t mix(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ull;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
  return x ^ (x >> 31);
}

}  // namespace

double position_hash_offset(const double* p, int d, int component, std::uint64_t salt) {
  std::uint64_t h = mix(salt ^ (static_cast<std::uint64_t>(component) << 56));
  for (int c = 0; c < d; ++c) {
    const double x = p[c] + 0.0;  // -0.0 -> 0.0
    std::uint64_t bits;
    std::memcpy(&bits, &x, sizeof bits);
    h = mix(h ^ bits);
  }
  // The top 53 bits as a double in [0, 1), then onto [-1, 1).
  return 2.0 * static_cast<double>(h >> 11) * 0x1.0p-53 - 1.0;
}

PointMatrix perturbed_by_position(const PointMatrix& points, double scale, std::uint64_t salt) {
  PointMatrix out = points;
  const int d = static_cast<int>(points.cols());
  for (Index r = 0; r < points.rows(); ++r)
    for (int c = 0; c < d; ++c) out(r, c) += scale * position_hash_offset(points.row(r).data(), d, c, salt);
  return out;
}

std::string failed_perturbations(const std::vector<std::pair<double, std::string>>& attempts) {
  std::ostringstream out;
  for (size_t a = 0; a < attempts.size();) {
    size_t b = a;  // the run of attempts that failed alike
    while (b + 1 < attempts.size() && attempts[b + 1].second == attempts[a].second) ++b;
    out << (a ? "; then " : "") << attempts[a].second << (a ? " at " : " with the inputs perturbed by ");
    for (size_t k = a; k <= b; ++k) out << (k == a ? "" : k == b ? " and " : ", ") << attempts[k].first;
    if (a == 0) out << " of their size";
    a = b + 1;
  }
  return out.str();
}

}  // namespace animanifold
