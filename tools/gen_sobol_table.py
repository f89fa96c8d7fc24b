#!/usr/bin/env python3
"""gen_sobol_table.py — writes kernels/sample/sobol_table.h, the generator matrices of
the Sobol' sequence for the first ST_SOBOL_DIMS dimensions, from Joe and
Kuo's direction numbers new-joe-kuo-6.21201 (S. Joe and F. Y. Kuo,
"Constructing Sobol sequences with better two-dimensional projections",
SIAM J. Sci. Comput. 30, 2635-2654, 2008; https://web.maths.unsw.edu.au/~fkuo/sobol/).

Input: the published text file (columns d s a m_i, one dimension a line after
a header line), or, without an argument, the same table as scipy ships it
(scipy/stats/_sobol_direction_numbers.npz: poly = x^s + a_1 x^(s-1) + ... + 1
as an integer, vinit = m_1..m_s).

Column k (k = 0..31) of dimension d is v_{k+1} = m_{k+1} 2^(32-(k+1)), the
first digit in the most significant bit, with Joe and Kuo's recurrence
  m_k = 2^s m_{k-s} xor m_{k-s} xor sum_{i=1}^{s-1} 2^i a_i m_{k-i};
dimension 0 is the van der Corput sequence (every m_k = 1).

Usage: tools/gen_sobol_table.py [new-joe-kuo-6.21201] > kernels/sample/sobol_table.h
"""
import sys

DIMS = 256

LICENCE = """\
 * Copyright (c) 2008, Frances Y. Kuo and Stephen Joe
 * All rights reserved.
 *
 * Redistribution and use in source and binary forms, with or without
 * modification, are permitted provided that the following conditions are met:
 *
 *   * Redistributions of source code must retain the above copyright notice,
 *     this list of conditions and the following disclaimer.
 *   * Redistributions in binary form must reproduce the above copyright
 *     notice, this list of conditions and the following disclaimer in the
 *     documentation and/or other materials provided with the distribution.
 *   * Neither the names of the copyright holders nor the names of the
 *     University of New South Wales and the University of Waikato and its
 *     contributors may be used to endorse or promote products derived from
 *     this software without specific prior written permission.
 *
 * THIS SOFTWARE IS PROVIDED BY THE COPYRIGHT HOLDERS ``AS IS'' AND ANY
 * EXPRESS OR IMPLIED WARRANTIES, INCLUDING, BUT NOT LIMITED TO, THE IMPLIED
 * WARRANTIES OF MERCHANTABILITY AND FITNESS FOR A PARTICULAR PURPOSE ARE
 * DISCLAIMED. IN NO EVENT SHALL THE COPYRIGHT HOLDERS BE LIABLE FOR ANY
 * DIRECT, INDIRECT, INCIDENTAL, SPECIAL, EXEMPLARY, OR CONSEQUENTIAL DAMAGES
 * (INCLUDING, BUT NOT LIMITED TO, PROCUREMENT OF SUBSTITUTE GOODS OR
 * SERVICES; LOSS OF USE, DATA, OR PROFITS; OR BUSINESS INTERRUPTION) HOWEVER
 * CAUSED AND ON ANY THEORY OF LIABILITY, WHETHER IN CONTRACT, STRICT
 * LIABILITY, OR TORT (INCLUDING NEGLIGENCE OR OTHERWISE) ARISING IN ANY WAY
 * OUT OF THE USE OF THIS SOFTWARE, EVEN IF ADVISED OF THE POSSIBILITY OF
 * SUCH DAMAGE."""


def read_published(path):
    """(s, a, [m_1..m_s]) of dimensions 1.. from the text file."""
    rows = []
    with open(path) as f:
        next(f)  # header: d s a m_i
        for line in f:
            d, s, a, *m = (int(t) for t in line.split())
            rows.append((s, a, m[:s]))
    return rows


def read_scipy():
    import numpy as np
    import scipy.stats
    import os
    path = os.path.join(os.path.dirname(scipy.stats.__file__), "_sobol_direction_numbers.npz")
    z = np.load(path)
    rows = []
    for poly, vinit in zip(z["poly"][1:], z["vinit"][1:]):
        poly = int(poly)
        s = poly.bit_length() - 1
        a = (poly >> 1) & ((1 << (s - 1)) - 1) if s > 1 else 0
        rows.append((s, a, [int(v) for v in vinit[:s]]))
    return rows


def columns(s, a, m):
    m = list(m)
    for k in range(s, 32):  # m[k] is m_{k+1}
        v = (m[k - s] << s) ^ m[k - s]
        for i in range(1, s):
            if (a >> (s - 1 - i)) & 1:
                v ^= m[k - i] << i
        m.append(v)
    return [m[k] << (31 - k) for k in range(32)]


def main():
    rows = read_published(sys.argv[1]) if len(sys.argv) > 1 else read_scipy()
    mats = [[1 << (31 - k) for k in range(32)]]
    mats += [columns(*r) for r in rows[: DIMS - 1]]
    out = sys.stdout
    out.write("/* sobol_table.h — the Sobol' generator matrices of dimensions 0..%d, generated\n" % (DIMS - 1))
    out.write(" * by tools/gen_sobol_table.py from Joe and Kuo's direction numbers\n")
    out.write(" * new-joe-kuo-6.21201 (the table scipy.stats.qmc.Sobol uses). Do not edit.\n")
    out.write(" * Column k of dimension d, st_sobol_matrix[32 d + k], is the 32-bit\n")
    out.write(" * direction number v_{k+1} (first digit in the most significant bit).\n *\n")
    out.write(" * The direction numbers are distributed under this licence:\n *\n")
    out.write(LICENCE + " */\n")
    out.write("#ifndef ST_SOBOL_TABLE_H\n#define ST_SOBOL_TABLE_H\n\n")
    out.write("#define ST_SOBOL_DIMS %du\n" % DIMS)
    out.write("ST_CONSTANT st_u32 st_sobol_matrix[ST_SOBOL_DIMS * 32u] = {\n")
    for d, cols in enumerate(mats):
        for k in range(0, 32, 8):
            out.write("    " + ", ".join("0x%08xu" % c for c in cols[k:k + 8]) + ",\n")
    out.write("};\n\n#endif\n")


if __name__ == "__main__":
    main()
