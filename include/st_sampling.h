/* st_sampling.h — the sampling module on the host (src/sampling/), in three
 * parts:
 *   1. the sampler as a concept: names, kinds, the check of a render's
 *      sampler settings and the preparation of st_params' sampler fields;
 *   2. the point sets of the laboratory (`strata pattern`), from the same
 *      functions of the shared kernel headers that the renderer runs;
 *   3. the pixel tiles of the tiled samplers (spp points in every pixel,
 *      uploaded once to the device by the renderer), toroidal Poisson-disk
 *      and best-candidate tiles of the unit square (without pixels), the star
 *      and L2-star discrepancy of a point set, its Fourier periodogram and the
 *      power spectrum of an image.
 * The per-sample sampler functions that the kernels run (radical inverse,
 * Halton, Hammersley, Sobol, ...) live in the shared kernel headers
 * (kernels/sample/samplers.h), not here.
 *
 * Conventions (part 3)
 *   - Points are float x,y pairs in [0,1)^2 unless a stride says otherwise.
 *   - Tiles are toroidal: every distance is measured on the unit torus,
 *     d(p,q)^2 = sum_k min(|p_k-q_k|, 1-|p_k-q_k|)^2, so a tile repeated on a
 *     grid stays a valid pattern across its seams.
 *   - Tile generators are deterministic: the same (count, seed) gives the same
 *     points, bit for bit, on every host. Their random numbers come from
 *     splitmix64 (Steele, Lea, Flood, "Fast Splittable Pseudorandom Number
 *     Generators", OOPSLA 2014); no global state, thread-safe.
 *   - Ownership: arrays returned through `float **points` are allocated here
 *     with malloc and freed by the caller with free(). On failure *points is
 *     NULL and nothing needs freeing. Input arrays are borrowed for the call.
 *   - Errors: ST_ERR_USAGE (bad argument, message names it), ST_ERR_NOMEM.
 *     Nothing here prints.
 *
 * Tests: tests/unit/test_sampling_*.c, one per part or file: settings (part 1),
 * kernels (kernels/sample/samplers.h), pattern (part 2), point_sets (poisson_*,
 * best_candidate_*, star_discrepancy_*, l2_star_*, spectrum_*), pixel_tile,
 * pmj02, spacing, image_spectrum. */
#ifndef ST_SAMPLING_HOST_H /* kernels/ may hold a shared header of the same file name */
#define ST_SAMPLING_HOST_H

#include "st_error.h"
#include "st_shared.h"

/* ---- 1. the sampler as a concept ---- */

/* The sampler as a concept on the host: names, what each kind is (per-pixel
 * or tiled, scrambled or not), the check of a render's sampler settings, and
 * the preparation of st_params' sampler fields. The tiles of the tiled
 * samplers are part 3's.
 *
 * A sampler is an ST_SAMPLER_* value (st_shared.h). Nothing here allocates or
 * prints; the check returns ST_ERR_USAGE with a message naming the field
 * ("spp 70000: ..."), which the CLI may rewrite as the option that sets it.
 *
 * Tests: tests/unit/test_sampling_settings.c (names, predicates, preparation, the Halton
 * check); tests/unit/test_sampling_kernels.c guards kernels/sample/samplers.h. */

/* Names, indexed by ST_SAMPLER_*. */
extern const char *const st_sampler_names[ST_SAMPLER_COUNT];
/* The ST_SAMPLER_* of a name, or -1. */
int st_sampler_lookup(const char *name);

/* Whether the scramble switch changes the sampler (stratified: the order of
 * its strata; halton, hammersley, sobol: digit scrambling). */
int st_sampler_takes_scramble(st_u32 sampler);

/* Whether the sampler places its points across pixels from a host-made tile
 * (poisson, best-candidate) rather than per pixel; the kernels test the same
 * ST_SAMPLER_IS_TILED. Per-pixel sampling is what filter importance sampling
 * and adaptive rounds need. */
int st_sampler_is_tiled(st_u32 sampler);

/* Checks that sampler is known and that its indices fit in 32 bits for a
 * width x height image at spp samples per pixel: Halton's global index is
 * stride * spp, with stride = 2^e2 3^e3 the pixel scales (st_sampler_prepare).
 * ST_ERR_USAGE naming the field ("sampler", "spp"). */
st_status st_sampler_check(st_u32 sampler, st_u32 width, st_u32 height, st_u32 spp,
                           st_error *err);

/* Fills p's sampler fields (stratified grid, Halton scales and their
 * inverses) from p->width, p->height and p->spp (pbrt-v4's HaltonSampler
 * constructor for the pixel scales). */
void st_sampler_prepare(st_params *p);

/* ---- 2. the laboratory's point sets ---- */

/* A sampler's point set as the laboratory sees it: the
 * samples of one pixel with spp = count, from the same functions of the
 * shared kernel headers that the renderer runs (kernels/sample/samplers.h), or, for
 * the tiled samplers, the lecture's patterns over the unit square (Bridson's
 * Poisson disk, Mitchell's best candidate; st_sampling_pattern_pixels gives
 * the renderer's tile, one point per pixel and pass, instead). So
 * `strata pattern --sampler halton --scramble none` prints
 * (Φ2(i), Φ3(i), Φ5(i), ...) and hammersley (i/N, Φ2(i), ...).
 * Tests: tests/unit/test_sampling_pattern.c. */

/* Largest --count and --dims. */
#define ST_SAMPLING_PATTERN_MAX_COUNT 1048576u
#define ST_SAMPLING_PATTERN_MAX_DIMS 256u

/* The first `dims` dimensions of `count` points of sampler `sampler`
 * (ST_SAMPLER_*), seed and scramble as for a render; *points holds
 * *out_count * dims floats in [0, 1), point-major, malloc'ed (caller frees).
 * *out_count equals count except for poisson, whose count is its target
 * (Bridson's radius follows from it: within 1 % from 256 points). */
st_status st_sampling_pattern(st_u32 sampler, st_u32 count, st_u32 dims, st_u32 seed,
                          st_u32 scramble, float **points, st_u32 *out_count, st_error *err);

/* The tiled samplers' (poisson, best-candidate) points as the renderer
 * places them: its tile (st_sampling_pixel_tile) of side x side pixels with
 * spp points in each, side = floor(sqrt(count)), spp = count / side^2 (so
 * *out_count = side^2 spp <= count), scaled to the unit square; later
 * dimensions as the renderer draws them. Errors: ST_ERR_USAGE (another
 * sampler, count or dims out of range), ST_ERR_NOMEM. */
st_status st_sampling_pattern_pixels(st_u32 sampler, st_u32 count, st_u32 dims, st_u32 seed,
                                     float **points, st_u32 *out_count, st_error *err);

/* Whether the pattern changes with the seed (spectra average over seeds). */
int st_sampling_pattern_is_random(st_u32 sampler, st_u32 scramble);

/* ---- 3. tiles, discrepancy and spectra ---- */

/* Largest tiles accepted: 2^22 Poisson points (~6 s, ~0.2 GiB of work
 * memory); 2^20 best-candidate points (minutes: see the cost below). */
#define ST_POISSON_MAX_COUNT 4194304u
#define ST_BEST_CANDIDATE_MAX_COUNT 1048576u

/* Poisson-disk packing used to pick the first radius: a Bridson tile with
 * k = 30 on the unit torus holds N ~= ST_POISSON_PACKING / r^2 points
 * (measured N r^2 = 0.6150..0.6155 for N = 4k..4M, 0.60..0.63 below 1k). For
 * scale, hexagonal packing, the densest possible, holds 2/sqrt(3) / r^2 =
 * 1.1547 / r^2, so r is 0.73 of the hexagonal spacing. */
#define ST_POISSON_PACKING 0.615
#define ST_POISSON_K 30u /* candidates per active point (Bridson 2007) */

/* Best-candidate: point n (0-based) is the best of
 *   m(n) = min(max(1, ST_BEST_CANDIDATE_K * n), ST_BEST_CANDIDATE_MAX_M)
 * uniform candidates: Mitchell's "candidates proportional to the points so
 * far", capped. Measured (minimum distance x sqrt(N) on the torus, 1024
 * points, seeds 1..8): k = 1, cap 1024: 0.54..0.76 (one early point with
 * few candidates can come close); k = 16, cap 4096: 0.77..0.78; cap 16384:
 * 0.78..0.79 at 3x the time. */
#define ST_BEST_CANDIDATE_K 16u
#define ST_BEST_CANDIDATE_MAX_M 4096u

/* Poisson-disk tile on the unit torus by Bridson's algorithm (R. Bridson, "Fast
 * Poisson Disk Sampling in Arbitrary Dimensions", SIGGRAPH 2007 sketch): a
 * background grid of cells no wider than r/sqrt(2) (at most one point each),
 * an active list, and k = ST_POISSON_K candidates drawn uniformly from the
 * annulus r <= d < 2r around a random active point; a candidate closer than r
 * (toroidally) to any point is rejected, and an active point with k failures
 * retires. The run ends when the active list is empty, which leaves the tile
 * nearly maximal (measured: ~0.1% of the torus is farther than r from every
 * point, no gap reaches 1.15 r).
 * The radius comes from target_count: r = sqrt(ST_POISSON_PACKING / target),
 * then up to 6 further runs rescale r by sqrt(count / target) until the count
 * is within 1% (or one point) of the target, keeping the closest run. Counts
 * land within 1% for targets >= 256 (tested: 2%); tiny targets can miss
 * further (a handful of disks on a torus cannot match every count).
 * Coordinates are multiples of 2^-24 (exact floats) and distances are
 * compared exactly on that lattice, so the guarantee below holds bit for bit.
 * Speed: ~1.1 M points/s for 4k..262k points, 0.9 M/s at 1M (one core of this
 * project's 2-vCPU VM, -O2; larger grids spill out of the caches).
 * Outputs: *points = 2 * *count floats (x,y pairs in [0,1)), malloc'ed, free()
 * by the caller; *count the number of points; *radius the radius r used:
 * every pair of points is at toroidal distance >= r. radius may be NULL.
 * Errors: ST_ERR_USAGE for target_count 0 or > ST_POISSON_MAX_COUNT or NULL
 * outputs, ST_ERR_NOMEM. */
st_status st_sampling_poisson_tile(st_u32 target_count, st_u32 seed, float **points,
                                   st_u32 *count, float *radius, st_error *err);

/* Best-candidate tile on the unit torus (D. P. Mitchell, "Spectrally Optimal
 * Sampling for Distribution Ray Tracing", SIGGRAPH 1991): point n is, among
 * m(n) uniform candidates (see ST_BEST_CANDIDATE_K above), the one whose
 * toroidal distance to the nearest of points 0..n-1 is largest (the first
 * candidate wins ties). Nearest-point queries go through a uniform grid that
 * is refined as points arrive (1..4 points per cell) and stop early once a
 * candidate cannot beat the best so far, so the result equals the brute-force
 * definition exactly (tested). Every prefix of the output is itself a
 * best-candidate pattern. Cost: sum over n of m(n) queries, about
 * count * min(16 count, ST_BEST_CANDIDATE_MAX_M): 0.6 s for 4096 points, ~13 s
 * for 65536 here.
 * Random stream: splitmix64 seeded with seed; each candidate draws x then y,
 * each the top 24 bits of one output times 2^-24.
 * Outputs: *points = 2 * count floats (x,y pairs in [0,1)), malloc'ed, free()
 * by the caller. Errors: ST_ERR_USAGE for count 0 or
 * > ST_BEST_CANDIDATE_MAX_COUNT or NULL points, ST_ERR_NOMEM. */
st_status st_sampling_best_candidate_tile(st_u32 count, st_u32 seed, float **points,
                                          st_error *err);

/* The tile the tiled samplers (poisson, best-candidate) render from: a torus
 * of side x side pixels with exactly spp points inside every pixel, spaced
 * as blue noise across pixel borders (src/sampling/pixel_tile.c). Built in spp
 * passes, each adding one point to every pixel:
 *   best-candidate: point n (0-based, over the whole tile) is, of
 *     m(n) = min(max(1, ST_PIXEL_TILE_K n), ST_PIXEL_TILE_MAX_M) candidates,
 *     the one whose toroidal distance to the nearest point so far is largest
 *     (Mitchell 1991: candidates in proportion to the points so far; the
 *     first wins ties). Each candidate is a pixel drawn uniformly from those
 *     still open in the pass (a list, 0..side^2-1 at the pass' start, the
 *     chosen pixel removed by moving the list's last into its place), then
 *     a uniform point inside it. k = 16: with k = 1 the first points of a
 *     small pattern (a pad table of 4 points: st_sampling_pad_tables) had
 *     1, 1, 2, 3 candidates, nearly random; k = 16 measured the same on
 *     large tiles and 5% lower soft-shadow error at 4 spp. Measured
 *     (minimum distance x sqrt(N) on the torus, 2^12..2^14 points): 0.56..0.58
 *     at 1 spp, 0.62 at 4, 0.71..0.74 at 16 to 1024; mean nearest-neighbour
 *     distance 0.84..0.88 (Mitchell's unconstrained pattern: 0.75 and 0.89;
 *     one point per pixel costs the smallest gaps at low spp). About 0.8 s
 *     for 2^14 points here.
 *   poisson: in a fresh random pixel order each pass, the first uniform
 *     dart inside the pixel at toroidal distance >= r from every point so
 *     far, r^2 = ST_PIXEL_TILE_PACKING / spp pixel^2 at first; when a pixel refuses ST_PIXEL_TILE_DARTS darts in a row the whole
 *     tile is remade with r 1/16 smaller. *radius (may be NULL) is the r of
 *     the tile returned (0 for best-candidate): every pair is >= r apart.
 * Coordinates are multiples of 2^-16 pixel; distances are exact integers.
 * Output: *points = 2 side^2 spp floats, point j = (x, y) in pixels, in
 * [0, side)^2, lying in pixel j mod side^2 (row-major), as its sample
 * j / side^2; malloc'ed, free() by the caller. Deterministic per (sampler,
 * side, spp, seed): one splitmix64 stream.
 * Errors: ST_ERR_USAGE (not a tiled sampler, side 0 or > 1024, spp 0, more
 * than ST_PIXEL_TILE_MAX_POINTS points, NULL points), ST_ERR_NOMEM. */
#define ST_PIXEL_TILE_K 16u      /* Mitchell's multiple: m = k n */
#define ST_PIXEL_TILE_MAX_M 1024u /* as ST_BEST_CANDIDATE_MAX_M */
#define ST_PIXEL_TILE_PACKING 0.5
#define ST_PIXEL_TILE_DARTS 256u
#define ST_PIXEL_TILE_MAX_POINTS 4194304u
st_status st_sampling_pixel_tile(st_u32 sampler, st_u32 side, st_u32 spp, st_u32 seed,
                                 float **points, float *radius, st_error *err);

/* The tables a tiled sampler (poisson, best-candidate) pads its later
 * dimensions from, as pbrt's pixel samplers pad theirs: ST_PMJ02_SETS tiles
 * of one pixel, each n = min(spp, ST_PAD_MAX_POINTS) points of the
 * sampler's own pattern on the unit torus (st_sampling_pixel_tile with side
 * 1, seed a hash of (seed, set)). Each pair of dimensions of a pixel reads
 * one set, chosen by a hash of (pixel, pair), at the pixel's sample index
 * permuted per (pixel, pair), under a toroidal shift per (pixel, pair) (and
 * per block of n samples past n): a shift on the torus keeps every distance,
 * so each pixel's samples are blue noise in every pair (samplers.h).
 * Output: *words = 2 ST_PMJ02_SETS n words, point j of set q at 2 (q n + j):
 * x, y as 32-bit binary fractions (exact: the tile's lattice is 2^-16);
 * *count = n. malloc'ed, free() by the caller. Errors: ST_ERR_USAGE (not a
 * tiled sampler, spp 0, NULL outputs), ST_ERR_NOMEM. */
st_status st_sampling_pad_tables(st_u32 sampler, st_u32 spp, st_u32 seed, st_u32 **words,
                                 st_u32 *count, st_error *err);

/* The scrambled Halton sampler's digit permutation tables for one seed
 * (src/sampling/halton.c), in the layout of samplers.h's
 * ST_HALTON_TABLE_HEADER: for every dimension 2 <= dim < ST_PRIME_COUNT and
 * every digit position a 32-bit index reaches, the image of each digit, so
 * that st_halton_dim equals its hashing definition bit for bit. *words
 * holds *count 32-bit words (the 16-bit entries in the host's byte order,
 * as the device reads them); malloc'ed, free() by the caller. Errors:
 * ST_ERR_USAGE (NULL outputs), ST_ERR_NOMEM. */
st_status st_sampling_halton_tables(st_u32 seed, st_u32 **words, size_t *count, st_error *err);

/* The tables of the pmj02 sampler (src/sampling/pmj02.c): `sets` progressive
 * multi-jittered (0,2) sequences of 2^log2n points each (Christensen, Kensler
 * and Kilpatrick 2018): every prefix of 2^m points is a (0,m,2)-net, each
 * elementary interval of area 2^-m, of every shape 2^-i x 2^-(m-i), holding
 * exactly one point. Output: *points = 2 sets 2^log2n words, point j of set
 * q at 2 (q 2^log2n + j): x, y as 32-bit binary fractions (value = word
 * 2^-32); malloc'ed, free() by the caller. Deterministic per (seed, set),
 * and the first 2^m points of a set do not depend on log2n.
 * Errors: ST_ERR_USAGE (log2n > ST_PMJ02_MAX_LOG2, sets 0 or more than
 * ST_PMJ02_SETS, NULL points), ST_ERR_NOMEM, ST_ERR_CHECK (no extension
 * found: never seen). */
st_status st_sampling_pmj02(st_u32 log2n, st_u32 sets, st_u32 seed, st_u32 **points,
                            st_error *err);

/* The tables of the pmj02bn sampler: st_sampling_pmj02's construction, each
 * new point the best of up to ST_PMJ02BN_CANDIDATES free darts of its
 * sub-quadrant, the one whose toroidal distance to the nearest point placed
 * so far is largest (Christensen, Kensler and Kilpatrick 2018, §6: pmj02bn,
 * as pbrt-v4's tables): every 2^m prefix stays a (0,m,2)-net and the points
 * are blue noise too. Same arguments, layout, limits and errors. */
#define ST_PMJ02BN_CANDIDATES 16u
st_status st_sampling_pmj02bn(st_u32 log2n, st_u32 sets, st_u32 seed, st_u32 **points,
                              st_error *err);

/* The renderer's tables for the pmj02bn sampler at spp samples per pixel
 * (at most 2^ST_PMJ02_MAX_LOG2): st_sampling_pmj02bn's ST_PMJ02_SETS sets of
 * 2^ceil(log2 spp) points (the later dimensions), then the pixel tile, as
 * pbrt-v4's GetSortedPMJ02BNPixelSamples makes it: one more pmj02bn
 * sequence of 2^ST_PMJ02_MAX_LOG2 points over a tile of T x T pixels, T² S
 * = 2^ST_PMJ02_MAX_LOG2 with S = 4^ceil(log4 spp), each pixel's S points in
 * sequence order (so every 2^m prefix of a pixel's points is a (0,m,2)-net
 * of the pixel, and the tile is blue noise across pixels), as fractions of
 * the pixel; pixel (x, y) of the tile at (y T + x) S, its point j at 2 (that
 * + j) words past the sets. *points malloc'ed, free() by the caller;
 * *words: its length. Errors: as st_sampling_pmj02bn (spp 0 or too many:
 * ST_ERR_USAGE). */
st_status st_sampling_pmj02bn_tables(st_u32 spp, st_u32 seed, st_u32 **points, size_t *words,
                                     st_error *err);

/* Exact star discrepancy of n points (x,y pairs, in [0,1)^2), the lecture's
 *   D*_N = sup over a,b in [0,1] of | #{x_i in [0,a)x[0,b)} / N - a*b |,
 * with closed boxes [0,a]x[0,b] included as limits of open ones. The sup is
 * attained at critical corners: the excess #/N - ab at closed boxes with a, b
 * point coordinates; the deficit ab - #/N at open boxes with a in {x_i} u {1},
 * b in {y_i} u {1}. O(N^2) time (N = 4096: 0.05 s here), O(N) memory.
 * Points with equal coordinates are handled. Returns NaN for n == 0,
 * pts == NULL, or when its O(N) scratch memory cannot be allocated. */
double st_star_discrepancy_2d(const float *pts, st_u32 n);

/* L2-star discrepancy T_N of n points of `dims` floats each, in [0,1)^dims,
 * by Warnock's formula (T. T. Warnock, "Computational investigations of
 * low-discrepancy point sets", in Applications of Number Theory to Numerical
 * Analysis, 1972):
 *   T_N^2 = 3^-d - (2^(1-d)/N) sum_i prod_k (1 - x_ik^2)
 *         + (1/N^2) sum_i sum_j prod_k (1 - max(x_ik, x_jk)),
 * which equals the integral over t in [0,1]^d of (#{x_i in [0,t)}/N - vol)^2.
 * O(N^2 d) (N = 4096, d = 2: 0.01 s here). Returns T_N (>= 0); NaN for
 * n == 0, dims == 0 or pts == NULL. */
double st_l2_star_discrepancy(const float *pts, st_u32 n, st_u32 dims);

/* The smallest distance between two of n points (x,y pairs in [0,1]^2),
 * measured in the unit square, or, with torus, per axis the shorter way
 * round the unit torus (a tile's own measure: it repeats). Exact: a grid
 * search, and every pair where the grid cannot decide (src/sampling/spacing.c).
 * Scaled by sqrt(n) it compares patterns of any size: a hexagonal lattice
 * has sqrt(2/sqrt(3)) = 1.075, Mitchell's best-candidate about 0.75.
 * NaN for n < 2, pts NULL, or no memory. */
double st_min_distance_2d(const float *pts, st_u32 n, int torus);

/* Largest kmax accepted by st_spectrum_periodogram. */
#define ST_SPECTRUM_KMAX_MAX 1024u /* work memory 16 (kmax+1)(2kmax+1) bytes */

/* Periodogram of n points: for integer k in [-kmax,kmax]^2,
 *   P(k) = |sum_j exp(-2 pi i k . x_j)|^2 / N,
 * ADDED (+=) to power[(ky + kmax) * (2kmax+1) + (kx + kmax)], so k = (0,0)
 * is the centre and callers can average over seeds (zero it first). Point j's
 * coordinates are pts[j*stride], pts[j*stride+1]. Exact direct sum in double:
 * per point, exp(-2 pi i k x) for all k comes from one sin/cos and a complex
 * recurrence (relative error ~ kmax * 1e-16); P(-k) = P(k) halves the work.
 * Measured against sin/cos per term: |error| < 2e-12 at kmax = 1024. Cost
 * n * (kmax+1) * (2kmax+1) complex multiply-adds (4096 points, kmax 64:
 * 0.04 s here). No FFT: the points are not on a grid, and gridding them (or a
 * non-uniform FFT) would not be exact.
 * Errors: ST_ERR_USAGE for NULL pointers, n == 0, stride < 2,
 * kmax > ST_SPECTRUM_KMAX_MAX; ST_ERR_NOMEM. */
st_status st_spectrum_periodogram(const float *pts, st_u32 n, st_u32 stride, st_u32 kmax,
                                  double *power, st_error *err);

/* Radial average of a centred (2kmax+1)^2 periodogram: bin b (0..kmax) is the
 * mean of P(k) over the k with round(|k|) == b, counts[b] their number.
 * Frequencies with round(|k|) > kmax (the corners) are left out. radial[] and
 * counts[] (both required) are overwritten, kmax+1 entries each. */
void st_spectrum_radial(const double *power, st_u32 kmax, double *radial, st_u32 *counts);

/* Power spectrum of a w x h image (row-major values, row 0 first):
 *   P(k) = |sum_x v(x) exp(-2 pi i (kx x / w + ky y / h))|^2 / (w h),
 * ADDED to power[((ky + h/2) mod h) w + (kx + w/2) mod w], so k = 0 sits at
 * (w/2, h/2) and callers can average over seeds. Independent values of
 * variance s^2 give E[P(k)] = s^2 at every k != 0. 2-D FFT by FFTW
 * (src/sampling/image_spectrum.c). Errors: ST_ERR_USAGE (NULL arrays, empty or more
 * than 2^28 pixels), ST_ERR_NOMEM. */
st_status st_spectrum_image(const double *values, st_u32 w, st_u32 h, double *power,
                            st_error *err);

#endif
