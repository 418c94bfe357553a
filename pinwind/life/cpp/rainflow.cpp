// Rainflow counting of a series of reversals, ASTM E1049-85 §5.4.4 (the three-point rule with
// the starting point counted in half cycles), pinwind.life._rainflow.
//
// A line-for-line port of extract_cycles of the maintained ``rainflow`` package (3.2), which
// pinwind used directly until the fatigue set's profile showed its Python loop taking half of
// each case (1.9 million cycles of 642 tooth histories: 32 of 70 s). The port keeps the
// package's arithmetic (range |x1 − x2|, mean 0.5 (x1 + x2), in the same order), so the cycles
// are bit-identical to the package's; tests/life/test_cycles.py checks that on random
// histories against the package itself.
#include <cmath>
#include <cstddef>
#include <utility>
#include <vector>

#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>

namespace nb = nanobind;

namespace {

using Array = nb::ndarray<nb::numpy, double, nb::ndim<1>>;
using Input = nb::ndarray<const double, nb::ndim<1>, nb::c_contig, nb::device::cpu>;

// Cycles as three columns: range, mean, count (1 for a full cycle, 0.5 for a half).
struct Cycles {
  std::vector<double> range, mean, count;

  void add(double x1, double x2, double n) {
    range.push_back(std::abs(x1 - x2));
    mean.push_back(0.5 * (x1 + x2));
    count.push_back(n);
  }
};

// The cycles of reversals (a strictly alternating series, first and last points included).
// With `flush` false the points not closed (the residue: the stack, its start first) are left
// in `residue` instead of being counted as half cycles: counting them with the next reversals
// after them is counting the series joined (the stack is all the state the rule keeps).
Cycles extract_cycles(const double* reversals, std::size_t n, bool flush = true,
                      std::vector<double>* residue = nullptr) {
  Cycles out;
  std::vector<double> points;  // the stack: points[head..] (head moves as the start is counted)
  points.reserve(64);
  std::size_t head = 0;
  for (std::size_t i = 0; i < n; ++i) {
    points.push_back(reversals[i]);
    while (points.size() - head >= 3) {
      const std::size_t m = points.size();
      const double x1 = points[m - 3], x2 = points[m - 2], x3 = points[m - 1];
      if (std::abs(x3 - x2) < std::abs(x2 - x1)) break;  // X < Y: read the next point
      if (m - head == 3) {
        out.add(points[head], points[head + 1], 0.5);  // Y holds the start: half a cycle
        ++head;
      } else {
        out.add(x1, x2, 1.0);  // a whole cycle: drop Y's peak and valley
        points[m - 3] = x3;
        points.resize(m - 2);
      }
    }
    if (head > 4096 && head * 2 > points.size()) {  // keep the stack from growing with the start
      points.erase(points.begin(), points.begin() + static_cast<std::ptrdiff_t>(head));
      head = 0;
    }
  }
  if (!flush) {
    residue->assign(points.begin() + static_cast<std::ptrdiff_t>(head), points.end());
    return out;
  }
  for (; points.size() - head > 1; ++head) out.add(points[head], points[head + 1], 0.5);
  return out;
}

Array to_numpy(std::vector<double>&& values) {
  auto* owned = new std::vector<double>(std::move(values));
  nb::capsule owner(owned, [](void* p) noexcept { delete static_cast<std::vector<double>*>(p); });
  return Array(owned->data(), {owned->size()}, owner);
}

}  // namespace

NB_MODULE(_rainflow, m) {
  m.doc() = "Rainflow counting of reversals (ASTM E1049-85 5.4.4), as the rainflow package counts";
  m.def(
      "extract_cycles",
      [](const Input& reversals) {
        Cycles c;
        {
          nb::gil_scoped_release release;
          c = extract_cycles(reversals.data(), reversals.shape(0));
        }
        return nb::make_tuple(to_numpy(std::move(c.range)), to_numpy(std::move(c.mean)),
                              to_numpy(std::move(c.count)));
      },
      nb::arg("reversals"),
      "(ranges, means, counts) of the rainflow cycles of a series of reversals, in the order "
      "rainflow.extract_cycles yields them.");
  m.def(
      "closed_cycles",
      [](const Input& reversals) {
        Cycles c;
        std::vector<double> residue;
        {
          nb::gil_scoped_release release;
          c = extract_cycles(reversals.data(), reversals.shape(0), false, &residue);
        }
        return nb::make_tuple(to_numpy(std::move(c.range)), to_numpy(std::move(c.mean)),
                              to_numpy(std::move(c.count)), to_numpy(std::move(residue)));
      },
      nb::arg("reversals"),
      "(ranges, means, counts, residue): the cycles extract_cycles yields before its last "
      "half cycles, and the points it would count them from (the stack, its start first). "
      "closed_cycles of the residue followed by more reversals continues the count; "
      "extract_cycles of the last residue gives the last half cycles.");
}
