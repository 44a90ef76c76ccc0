#!/usr/bin/python3
"""Sobol' indices by OpenTURNS on a pick-and-freeze design's outputs, for
tests/analysis/sensitivity_test.cpp.

Usage: openturns_sobol.py FILE

FILE: first line "N G" (rows, groups), then the (G + 2) N outputs one per line: f(A_j)
for j = 0..N-1, then f(B_j), then f(AB_0,j), ..., f(AB_G-1,j). That is OpenTURNS' own
layout (SobolIndicesExperiment: A, B, then E^i = A with column i taken from B, which is
our AB_g), so the outputs go in unchanged. OpenTURNS only reads the input design's
dimension (one column per group) and size, so a dummy input design of G columns carries
groups of several inputs.

Prints one "key index value" line per number (value with 17 significant digits):
  openturns_version 0 VERSION
  reference_variance 0 V  the variance OpenTURNS divides by: Sample.computeVariance() of
                          f(A) after centring on the mean of all outputs (unbiased, N - 1)
  martinez_first g V, martinez_total g V        MartinezSensitivityAlgorithm
  jansen_total g V                              JansenSensitivityAlgorithm, total order
  mauntz_kucherenko_first g V                   MauntzKucherenkoSensitivityAlgorithm, first order
  janon_first g V    Janon et al. (2014) on the pair (B, AB_g), computed here with numpy:
                     OpenTURNS 1.20 (Debian 12) has no Janon estimator.

Exits 2 with a message on stderr if OpenTURNS cannot be imported.
"""
import sys

try:
    import openturns as ot
except ImportError as error:  # a required test dependency (.ci/packages: python3-openturns)
    sys.stderr.write("openturns_sobol.py: cannot import openturns (Debian package python3-openturns): %s\n" % error)
    sys.exit(2)
import numpy as np


def main():
    if len(sys.argv) != 2:
        sys.stderr.write("usage: openturns_sobol.py FILE\n")
        return 1
    with open(sys.argv[1]) as stream:
        rows, groups = (int(word) for word in stream.readline().split())
        values = np.array([float(line) for line in stream if line.strip()])
    if values.size != (groups + 2) * rows:
        sys.stderr.write("openturns_sobol.py: %d outputs for N = %d, G = %d\n" % (values.size, rows, groups))
        return 1
    ot.Log.Show(ot.Log.NONE)  # no warnings about indices outside [0, 1] on stdout/stderr
    output_design = ot.Sample(values.reshape(-1, 1))
    input_design = ot.Sample((groups + 2) * rows, groups)

    def line(key, index, value):
        print("%s %d %.17g" % (key, index, value))

    print("openturns_version 0 %s" % ot.__version__)
    centred = values - values.mean()
    line("reference_variance", 0, ot.Sample(centred[:rows].reshape(-1, 1)).computeVariance()[0])
    martinez = ot.MartinezSensitivityAlgorithm(input_design, output_design, rows)
    jansen = ot.JansenSensitivityAlgorithm(input_design, output_design, rows)
    mauntz = ot.MauntzKucherenkoSensitivityAlgorithm(input_design, output_design, rows)
    for g, value in enumerate(martinez.getFirstOrderIndices()):
        line("martinez_first", g, value)
    for g, value in enumerate(martinez.getTotalOrderIndices()):
        line("martinez_total", g, value)
    for g, value in enumerate(jansen.getTotalOrderIndices()):
        line("jansen_total", g, value)
    for g, value in enumerate(mauntz.getFirstOrderIndices()):
        line("mauntz_kucherenko_first", g, value)

    b = values[rows:2 * rows]
    for g in range(groups):
        ab = values[(2 + g) * rows:(3 + g) * rows]
        mean = 0.5 * (b.mean() + ab.mean())
        line("janon_first", g, (np.mean(b * ab) - mean**2) / (0.5 * np.mean(b * b + ab * ab) - mean**2))
    return 0


if __name__ == "__main__":
    sys.exit(main())
