// The inner loops of the linear rung's path sums (solvers/linear.cpp): turning a set of
// phasors through consecutive angles (in lane groups, or one angle at a time through a
// run), and weighted sums of the rows of such a table. Each
// exists in two builds chosen at run time: baseline x86-64 (SSE2, what any x86-64 runs)
// and AVX2 (twice the lanes an instruction).
//
// Contract: for every lane (angle), both builds perform the same IEEE-754 double
// operations in the same order (every product rounded, then every sum; no fused
// multiply-add: path_kernels.cpp is compiled with -ffp-contract=off and its AVX2 build does
// not enable FMA), so their results are bit-for-bit equal and the choice changes speed
// only. tests/solvers/path_kernels_test.cpp compares the bits.
//
// Pure functions of their arguments: thread-safe; they neither own nor allocate memory,
// and the caller guarantees every pointer spans what the comments say (no checks).
#pragma once

#include <cstddef>

namespace ringtol::solvers::path_kernels {

// Angles a phasor turn handles together; every lane count below is a multiple of it.
inline constexpr std::size_t kLanes = 8;

enum class Isa {
  kBest,      // AVX2 where the CPU has it, else baseline
  kBaseline,  // SSE2, every x86-64
  kAvx2,      // AVX2; where the CPU lacks it, the baseline is used instead
};

// Phasors of `terms` error terms, each turning at its own rate through angles psi_k.
struct Phasors {
  std::size_t terms = 0;
  const double* lane_cos = nullptr;   // [terms x kLanes] turn by 0 .. kLanes - 1 increments
  const double* lane_sin = nullptr;   // [terms x kLanes]
  const double* group_cos = nullptr;  // [terms] turn by kLanes increments
  const double* group_sin = nullptr;  // [terms]
  double* now_cos = nullptr;          // [terms] phasor at the lane group's first angle;
  double* now_sin = nullptr;          //         advanced by kLanes increments on return
};

// Weights of a set of rows over a table's rows: weight[o * terms + q]; for row o only the
// terms [first[o], last[o]) are read (its weights outside are zero).
struct WeightedRows {
  std::size_t rows = 0;
  std::size_t terms = 0;
  const double* weight = nullptr;       // [rows x terms]
  const std::size_t* first = nullptr;   // [rows]
  const std::size_t* last = nullptr;    // [rows]
};

struct Kernels {
  Isa isa = Isa::kBaseline;  // which build these are (never kBest)
  // For each term p, one lane group of kLanes angles:
  //   table[p * term_stride + l]              = now_cos lane_cos[l] - now_sin lane_sin[l]
  //   table[p * term_stride + sin_offset + l] = now_sin lane_cos[l] + now_cos lane_sin[l]
  // then (now_cos, now_sin) turned by (group_cos, group_sin), in that formula's order.
  void (*turn_phasors)(const Phasors& phasors, double* table, std::size_t term_stride, std::size_t sin_offset) = nullptr;
  // For each term p < terms and angle j < count, from (cos_0, sin_0) = (now_cos[p], now_sin[p]):
  //   table[2 p stride + j] = cos_j,  table[(2 p + 1) stride + j] = sin_j,
  //   cos_j+1 = cos_j turn_cos[p] - sin_j turn_sin[p],  sin_j+1 = sin_j turn_cos[p] + cos_j turn_sin[p]
  // in that formula's order; (now_cos[p], now_sin[p]) are left at (cos_count, sin_count),
  // and lanes j >= count are not written.
  void (*turn_run)(std::size_t terms, double* now_cos, double* now_sin, const double* turn_cos, const double* turn_sin,
                   std::size_t count, double* table, std::size_t stride) = nullptr;
  // For every row o and lane j < lanes (a multiple of kLanes):
  //   out[o * out_stride + j] = sum over q ascending of weight(o, q) * table[q * table_stride + j],
  // accumulated from +0 one rounded product at a time.
  void (*sum_rows)(const WeightedRows& rows, const double* table, std::size_t table_stride, std::size_t lanes,
                   double* out, std::size_t out_stride) = nullptr;
};

// Whether this CPU runs isa's build (kBest and kBaseline: always).
bool Supported(Isa isa);

// The kernels of isa, or of the baseline where isa is not supported.
const Kernels& KernelsFor(Isa isa);

}  // namespace ringtol::solvers::path_kernels
