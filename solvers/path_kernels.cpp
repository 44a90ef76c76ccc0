#include "solvers/path_kernels.h"

// Bit-for-bit equality of the builds rests on every multiply and add being rounded on its
// own: solvers/CMakeLists.txt compiles this file with -ffp-contract=off, so that no build
// fuses them, even one for a CPU with FMA (-march=native).

namespace ringtol::solvers::path_kernels {
namespace {

// Four doubles as one GCC vector: an AVX2 register, or two SSE2 registers in the baseline
// build, which the compiler splits lane by lane without changing any lane's operations.
using V4 = double __attribute__((vector_size(32)));
constexpr std::size_t kV4 = 4;

// Never passed to or returned from a call (the ABI of a 32-byte vector depends on the
// build): loaded and stored through memcpy, which also needs no alignment. The helpers
// below are inlined into each build, and take its instructions there.
#define RINGTOL_INLINE [[gnu::always_inline]] inline

template <std::size_t kChunk>
RINGTOL_INLINE void SumChunk(const double* weight, std::size_t first, std::size_t last, const double* table,
                             std::size_t table_stride, double* out) {
  constexpr std::size_t n = kChunk / kV4;
  V4 sum[n];
  for (std::size_t v = 0; v < n; ++v) sum[v] = V4{0.0, 0.0, 0.0, 0.0};
  const double* values = table + first * table_stride;
  for (std::size_t q = first; q < last; ++q, values += table_stride) {
    const double x = weight[q];
    const V4 w = {x, x, x, x};
    for (std::size_t v = 0; v < n; ++v) {
      V4 t;
      __builtin_memcpy(&t, values + v * kV4, sizeof t);
      sum[v] += w * t;
    }
  }
  __builtin_memcpy(out, sum, sizeof sum);
}

// kChunk lanes at a time with kChunk / 4 independent sums: enough to hide the adder's
// latency, few enough to stay in registers (16 SSE2 or 16 AVX2 registers).
template <std::size_t kChunk>
RINGTOL_INLINE void SumRowsBody(const WeightedRows& rows, const double* table, std::size_t table_stride,
                                std::size_t lanes, double* out, std::size_t out_stride) {
  for (std::size_t o = 0; o < rows.rows; ++o) {
    const double* weight = rows.weight + o * rows.terms;
    const std::size_t first = rows.first[o];
    const std::size_t last = rows.last[o];
    double* row = out + o * out_stride;
    std::size_t j = 0;
    for (; j + kChunk <= lanes; j += kChunk) SumChunk<kChunk>(weight, first, last, table + j, table_stride, row + j);
    for (; j < lanes; j += kLanes) SumChunk<kLanes>(weight, first, last, table + j, table_stride, row + j);
  }
}

RINGTOL_INLINE void TurnPhasorsBody(const Phasors& phasors, double* table, std::size_t term_stride,
                                    std::size_t sin_offset) {
  static_assert(kLanes % kV4 == 0);
  for (std::size_t p = 0; p < phasors.terms; ++p) {
    const double now_cos = phasors.now_cos[p];
    const double now_sin = phasors.now_sin[p];
    const V4 c = {now_cos, now_cos, now_cos, now_cos};
    const V4 s = {now_sin, now_sin, now_sin, now_sin};
    double* cos_out = table + p * term_stride;
    double* sin_out = cos_out + sin_offset;
    for (std::size_t v = 0; v < kLanes; v += kV4) {
      V4 lane_cos, lane_sin;
      __builtin_memcpy(&lane_cos, phasors.lane_cos + p * kLanes + v, sizeof lane_cos);
      __builtin_memcpy(&lane_sin, phasors.lane_sin + p * kLanes + v, sizeof lane_sin);
      const V4 turned_cos = c * lane_cos - s * lane_sin;
      const V4 turned_sin = s * lane_cos + c * lane_sin;
      __builtin_memcpy(cos_out + v, &turned_cos, sizeof turned_cos);
      __builtin_memcpy(sin_out + v, &turned_sin, sizeof turned_sin);
    }
    phasors.now_cos[p] = now_cos * phasors.group_cos[p] - now_sin * phasors.group_sin[p];
    phasors.now_sin[p] = now_sin * phasors.group_cos[p] + now_cos * phasors.group_sin[p];
  }
}

// A 4 x 4 block transposed: rows[a][b] becomes rows[b][a].
RINGTOL_INLINE void Transpose(V4 (&rows)[kV4]) {
  const V4 low01 = __builtin_shufflevector(rows[0], rows[1], 0, 4, 2, 6);
  const V4 high01 = __builtin_shufflevector(rows[0], rows[1], 1, 5, 3, 7);
  const V4 low23 = __builtin_shufflevector(rows[2], rows[3], 0, 4, 2, 6);
  const V4 high23 = __builtin_shufflevector(rows[2], rows[3], 1, 5, 3, 7);
  rows[0] = __builtin_shufflevector(low01, low23, 0, 1, 4, 5);
  rows[1] = __builtin_shufflevector(high01, high23, 0, 1, 4, 5);
  rows[2] = __builtin_shufflevector(low01, low23, 2, 3, 6, 7);
  rows[3] = __builtin_shufflevector(high01, high23, 2, 3, 6, 7);
}

// kRunTerms terms at a time, as independent chains of products (two vectors: enough to
// hide the multiplier's latency), four angles a step: the block of four angles by four
// terms is transposed in registers and stored a row's four lanes at once, where a term's
// every angle took a store of its own.
constexpr std::size_t kRunTerms = 4;

RINGTOL_INLINE void TurnRunBody(std::size_t terms, double* now_cos, double* now_sin, const double* turn_cos,
                                const double* turn_sin, std::size_t count, double* table, std::size_t stride) {
  constexpr std::size_t n = kRunTerms / kV4;
  for (std::size_t first = 0; first < terms; first += kRunTerms) {
    const std::size_t block = terms - first < kRunTerms ? terms - first : kRunTerms;
    // A block of fewer terms is padded with phasors at rest, whose rows are not stored.
    double start[4][kRunTerms];
    for (std::size_t b = 0; b < kRunTerms; ++b) {
      const bool term = b < block;
      start[0][b] = term ? now_cos[first + b] : 1.0;
      start[1][b] = term ? now_sin[first + b] : 0.0;
      start[2][b] = term ? turn_cos[first + b] : 1.0;
      start[3][b] = term ? turn_sin[first + b] : 0.0;
    }
    V4 c[n], s[n], tc[n], ts[n];
    __builtin_memcpy(c, start[0], sizeof c);
    __builtin_memcpy(s, start[1], sizeof s);
    __builtin_memcpy(tc, start[2], sizeof tc);
    __builtin_memcpy(ts, start[3], sizeof ts);
    for (std::size_t j = 0; j < count; j += kV4) {
      V4 cos_at[n][kV4], sin_at[n][kV4];  // [terms 4v .. 4v + 3][angle j + a]
      for (std::size_t a = 0; a < kV4; ++a) {
        for (std::size_t v = 0; v < n; ++v) {
          cos_at[v][a] = c[v];
          sin_at[v][a] = s[v];
          const V4 next = c[v] * tc[v] - s[v] * ts[v];
          s[v] = s[v] * tc[v] + c[v] * ts[v];
          c[v] = next;
        }
      }
      // The run's last angles: the phasors stop at angle `count`, turned no further.
      const std::size_t lanes = count - j < kV4 ? count - j : kV4;
      if (lanes < kV4) {
        for (std::size_t v = 0; v < n; ++v) {
          c[v] = cos_at[v][lanes];
          s[v] = sin_at[v][lanes];
        }
      }
      for (std::size_t v = 0; v < n; ++v) {
        Transpose(cos_at[v]);
        Transpose(sin_at[v]);
        // Constant trip counts and lane indices throughout, so that the block stays in
        // registers.
        for (std::size_t a = 0; a < kV4; ++a) {
          if (kV4 * v + a >= block) continue;
          double* cos_row = table + 2 * (first + kV4 * v + a) * stride + j;
          if (lanes == kV4) {
            __builtin_memcpy(cos_row, &cos_at[v][a], sizeof(V4));
            __builtin_memcpy(cos_row + stride, &sin_at[v][a], sizeof(V4));
            continue;
          }
          for (std::size_t l = 0; l + 1 < kV4; ++l) {
            if (l < lanes) {
              cos_row[l] = cos_at[v][a][l];
              cos_row[stride + l] = sin_at[v][a][l];
            }
          }
        }
      }
    }
    __builtin_memcpy(start[0], c, sizeof c);
    __builtin_memcpy(start[1], s, sizeof s);
    for (std::size_t b = 0; b < block; ++b) {
      now_cos[first + b] = start[0][b];
      now_sin[first + b] = start[1][b];
    }
  }
}

void SumRowsBaseline(const WeightedRows& rows, const double* table, std::size_t table_stride, std::size_t lanes,
                     double* out, std::size_t out_stride) {
  SumRowsBody<16>(rows, table, table_stride, lanes, out, out_stride);
}

void TurnPhasorsBaseline(const Phasors& phasors, double* table, std::size_t term_stride, std::size_t sin_offset) {
  TurnPhasorsBody(phasors, table, term_stride, sin_offset);
}

void TurnRunBaseline(std::size_t terms, double* now_cos, double* now_sin, const double* turn_cos, const double* turn_sin,
                     std::size_t count, double* table, std::size_t stride) {
  TurnRunBody(terms, now_cos, now_sin, turn_cos, turn_sin, count, table, stride);
}

#if defined(__x86_64__) && defined(__GNUC__)
#define RINGTOL_HAVE_AVX2_BUILD 1

__attribute__((target("avx2"))) void SumRowsAvx2(const WeightedRows& rows, const double* table,
                                                 std::size_t table_stride, std::size_t lanes, double* out,
                                                 std::size_t out_stride) {
  SumRowsBody<32>(rows, table, table_stride, lanes, out, out_stride);
}

__attribute__((target("avx2"))) void TurnPhasorsAvx2(const Phasors& phasors, double* table, std::size_t term_stride,
                                                     std::size_t sin_offset) {
  TurnPhasorsBody(phasors, table, term_stride, sin_offset);
}

__attribute__((target("avx2"))) void TurnRunAvx2(std::size_t terms, double* now_cos, double* now_sin,
                                                 const double* turn_cos, const double* turn_sin, std::size_t count,
                                                 double* table, std::size_t stride) {
  TurnRunBody(terms, now_cos, now_sin, turn_cos, turn_sin, count, table, stride);
}
#endif

constexpr Kernels kBaselineKernels{Isa::kBaseline, &TurnPhasorsBaseline, &TurnRunBaseline, &SumRowsBaseline};
#ifdef RINGTOL_HAVE_AVX2_BUILD
constexpr Kernels kAvx2Kernels{Isa::kAvx2, &TurnPhasorsAvx2, &TurnRunAvx2, &SumRowsAvx2};
#endif

bool CpuHasAvx2() {
#ifdef RINGTOL_HAVE_AVX2_BUILD
  static const bool has = __builtin_cpu_supports("avx2");
  return has;
#else
  return false;
#endif
}

}  // namespace

bool Supported(Isa isa) { return isa != Isa::kAvx2 || CpuHasAvx2(); }

const Kernels& KernelsFor(Isa isa) {
#ifdef RINGTOL_HAVE_AVX2_BUILD
  if (isa != Isa::kBaseline && CpuHasAvx2()) return kAvx2Kernels;
#endif
  static_cast<void>(isa);  // used only where an AVX2 build exists
  return kBaselineKernels;
}

}  // namespace ringtol::solvers::path_kernels

#undef RINGTOL_INLINE
