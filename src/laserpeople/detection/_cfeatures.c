/* The fourteen segment features of features.py's _compute, compiled: every segment of a
 * block of scans in one call per pass, arrays in, arrays out (and, at the end of this file,
 * the AdaBoost margins of adaboost._StumpTables.evaluate: the groups' table values at
 * each value's rank, added in group order as its cumulative sum adds them; before them
 * a scan's validity and points (scan.Scan's cached arrays), the jumps between neighbouring
 * points of segmentation.at_least, the segments of a block of scans
 * (segmentation._block_starts) and its sparse legs (detection/sparse.py's _sparse)).
 *
 * The same IEEE double operations in the same order as the numpy reference (build with
 * -ffp-contract=off: no fused multiply-add):
 *   - np.add.reduceat sums (centres, centred moments, distances to the medians, circle
 *     residuals) are the first term plus numpy's pairwise sum of the rest
 *     (pairwise_sum below: 8 accumulators up to 128 terms, halves at multiples of 8 above);
 *   - np.bincount sums (boundary length, curvature, turning angles, the beams' range
 *     changes, the steps' squared deviations) add in point order from 0.0;
 *   - the vector of medians takes the middle elements of each coordinate within its
 *     segment in the order of the reference's stable argsort (by the key coordinate +
 *     interval * span, ties in point order), found by quickselect;
 *   - hypot, sqrt, cos and sin are the C library's, as numpy's on x86-64 and aarch64.
 * atan2 is not computed here: numpy's arctan2 is SIMD code (SVML on AVX-512) that differs
 * from the C library's in the last bit of some values, so pass1 returns the arguments of
 * every atan2 (turning angles, then line-fit angles) and pass2 takes numpy's results.
 *
 * C99, the CPython C API only (the buffer protocol for arrays). setup.py compiles this
 * file's checksum in as LP_SOURCE_HASH; detection/compiled_features.py runs the Python
 * features when the file beside the module has another one.
 */
#define PY_SSIZE_T_CLEAN
#include <Python.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../_cbuffers.h"

#ifndef LP_SOURCE_HASH
#define LP_SOURCE_HASH ""
#endif

#define N_FEATURES 14
#define N_WORK 6 /* sxx, syy, sxy, sxz, syz, sz per segment */
#define PW_BLOCKSIZE 128

/* numpy's pairwise sum of n doubles a[0], a[stride], ... (loops_utils.h.src) */
static double pairwise_sum(const double *a, Py_ssize_t n, Py_ssize_t stride) {
    if (n < 8) {
        double res = -0.0;
        for (Py_ssize_t i = 0; i < n; i++) res += a[i * stride];
        return res;
    }
    if (n <= PW_BLOCKSIZE) {
        double r[8];
        Py_ssize_t i;
        for (int j = 0; j < 8; j++) r[j] = a[j * stride];
        for (i = 8; i < n - (n % 8); i += 8)
            for (int j = 0; j < 8; j++) r[j] += a[(i + j) * stride];
        double res = ((r[0] + r[1]) + (r[2] + r[3])) + ((r[4] + r[5]) + (r[6] + r[7]));
        for (; i < n; i++) res += a[i * stride];
        return res;
    }
    Py_ssize_t n2 = n / 2;
    n2 -= n2 % 8;
    return pairwise_sum(a, n2, stride) + pairwise_sum(a + n2 * stride, n - n2, stride);
}

/* np.add.reduceat's sum of one segment: its first term plus the pairwise sum of the rest */
static double reduce_sum(const double *a, Py_ssize_t n, Py_ssize_t stride) {
    double s = a[0];
    if (n > 1) s += pairwise_sum(a + stride, n - 1, stride);
    return s;
}

typedef struct {
    double key;
    double value;
    Py_ssize_t at;
} Keyed;

/* whether a comes before b in the stable sort: by key, ties in point order */
static inline int before(const Keyed *a, const Keyed *b) {
    return a->key < b->key || (a->key == b->key && a->at < b->at);
}

/* Reorder v[0..n) so that v[j] is the element at j in the stable sort, those before it
 * come before it and those after it after it (quickselect; the points' order breaks ties,
 * so no two elements are equal). */
static void select_at(Keyed *v, Py_ssize_t n, Py_ssize_t j) {
    Py_ssize_t lo = 0, hi = n - 1;
    while (hi - lo >= 16) {
        Py_ssize_t mid = lo + (hi - lo) / 2;
        Keyed tmp;
        if (before(&v[mid], &v[lo])) tmp = v[mid], v[mid] = v[lo], v[lo] = tmp;
        if (before(&v[hi], &v[lo])) tmp = v[hi], v[hi] = v[lo], v[lo] = tmp;
        if (before(&v[hi], &v[mid])) tmp = v[hi], v[hi] = v[mid], v[mid] = tmp;
        Keyed pivot = v[mid];
        Py_ssize_t a = lo, b = hi;
        while (a <= b) {
            while (before(&v[a], &pivot)) a++;
            while (before(&pivot, &v[b])) b--;
            if (a <= b) {
                tmp = v[a], v[a] = v[b], v[b] = tmp;
                a++;
                b--;
            }
        }
        if (j <= b)
            hi = b;
        else if (j >= a)
            lo = a;
        else
            return; /* (v[j] is the pivot) */
    }
    for (Py_ssize_t i = lo + 1; i <= hi; i++) { /* insertion sort of the rest */
        Keyed x = v[i];
        Py_ssize_t q = i;
        for (; q > lo && before(&x, &v[q - 1]); q--) v[q] = v[q - 1];
        v[q] = x;
    }
}

/* The median of one segment's coordinate (values at stride 2), as features._sorted_within
 * orders it: by value + interval * span, ties in point order. */
static double median_of(const double *v, Py_ssize_t n, double interval, double span,
                        Keyed *scratch) {
    double base = interval * span;
    for (Py_ssize_t i = 0; i < n; i++) {
        scratch[i].key = v[2 * i] + base;
        scratch[i].value = v[2 * i];
        scratch[i].at = i;
    }
    Py_ssize_t lo = (n - 1) / 2, hi = n / 2;
    select_at(scratch, n, lo);
    const Keyed *upper = &scratch[lo];
    if (hi != lo) { /* the first after v[lo] in the sort: the least of those after it */
        upper = &scratch[hi];
        for (Py_ssize_t i = hi + 1; i < n; i++)
            if (before(&scratch[i], upper)) upper = &scratch[i];
    }
    return 0.5 * (scratch[lo].value + upper->value);
}

/* The span of the medians' sort key over all points P (K, 2), as _sorted_within. */
static double key_span(const double *P, Py_ssize_t k) {
    double big = 0.0;
    for (Py_ssize_t i = 0; i < 2 * k; i++)
        if (fabs(P[i]) > big) big = fabs(P[i]);
    return 2.0 * big + 1.0;
}

/* Feature 3 of segment s of m (its n points p at stride 2): the mean distance to the
 * vector of medians (md: n doubles of scratch). */
static double mad_median(const double *p, Py_ssize_t n, Py_ssize_t s, Py_ssize_t m,
                         double span, Keyed *keyed, double *md) {
    double medx = median_of(p, n, (double)s, span, keyed);
    double medy = median_of(p + 1, n, (double)(m + s), span, keyed);
    for (Py_ssize_t i = 0; i < n; i++) md[i] = hypot(p[2 * i] - medx, p[2 * i + 1] - medy);
    return reduce_sum(md, n, 1) / (double)n;
}

/* Features 8, 9: the algebraic circle fit of a segment of n points from its centred
 * moments w (N_WORK): the centre (xc, yc) relative to the centroid and the radius rc;
 * whether it has a circle (not collinear). */
static int circle_fit(const double *w, Py_ssize_t n, double *xc, double *yc, double *rc) {
    double sxx = w[0], syy = w[1], sxy = w[2], sxz = w[3], syz = w[4], sz = w[5];
    double det = sxx * syy - sxy * sxy;
    double scale = (sxx + syy) * (sxx + syy);
    int has_circle = n >= 3 && det > 1e-12 * scale && scale > 0.0;
    *xc = 0.0;
    *yc = 0.0;
    if (has_circle) {
        double safe = 2.0 * det;
        *xc = (syy * sxz - sxy * syz) / safe;
        *yc = (sxx * syz - sxy * sxz) / safe;
    }
    *rc = sqrt(*xc * *xc + *yc * *yc + sz / (double)n);
    return has_circle;
}

/* Feature 8 of a segment with a circle: the residual sum of squares of its n points p
 * (stride 2) to the circle (xc, yc, rc) about the centroid (cx, cy) (r2: n doubles). */
static double circle_residual(const double *p, Py_ssize_t n, double cx, double cy, double xc,
                              double yc, double rc, double *r2) {
    for (Py_ssize_t i = 0; i < n; i++) {
        double dx = p[2 * i] - cx, dy = p[2 * i + 1] - cy;
        double r = rc - hypot(dx - xc, dy - yc);
        r2[i] = r * r;
    }
    return reduce_sum(r2, n, 1);
}

/* features._beam_changes: every point's range change since the same beam of the previous
 * scan, delta (K,), 1.0 in both (K,) where that beam is valid in both scans, and each
 * segment's time since the previous scan dt (M,) (1.0 for the tables without one). */
static int beam_changes(PyObject *changes, const long long *off, const long long *tables,
                        Py_ssize_t t_count, Py_ssize_t m, double *delta, double *both,
                        double *dt) {
    for (Py_ssize_t s = 0; s < m; s++) dt[s] = 1.0;
    for (Py_ssize_t q = 0; q < t_count; q++) {
        PyObject *item = PyList_GET_ITEM(changes, q);
        if (item == Py_None) continue;
        if (!PyTuple_CheckExact(item) || PyTuple_GET_SIZE(item) != 5) {
            PyErr_SetString(PyExc_ValueError,
                            "changes: (beams, ranges, previous ranges, previous valid, dt)");
            return -1;
        }
        double since = PyFloat_AsDouble(PyTuple_GET_ITEM(item, 4));
        if (since == -1.0 && PyErr_Occurred()) return -1;
        Py_ssize_t first = off[tables[q]], count = off[tables[q + 1]] - first;
        Buf v[4];
        memset(v, 0, sizeof(v));
        int failed = take(PyTuple_GET_ITEM(item, 0), &v[0], 1, 0, count, "beams") < 0 ||
                     take(PyTuple_GET_ITEM(item, 1), &v[1], 0, 0, -1, "ranges") < 0;
        Py_ssize_t n_beams = failed ? 0 : v[1].view.len / 8;
        failed = failed || take(PyTuple_GET_ITEM(item, 2), &v[2], 0, 0, n_beams, "ranges") < 0;
        failed = failed || take_bools(PyTuple_GET_ITEM(item, 3), &v[3], n_beams, "valid") < 0;
        if (!failed) {
            const long long *beams = v[0].view.buf;
            const double *now = v[1].view.buf, *before = v[2].view.buf;
            const char *valid = v[3].view.buf;
            for (Py_ssize_t i = 0; i < count; i++) {
                long long beam = beams[i] < 0 ? beams[i] + n_beams : beams[i];
                if (beam < 0 || beam >= n_beams) {
                    PyErr_SetString(PyExc_IndexError, "beams: a beam outside the scan");
                    failed = 1;
                    break;
                }
                if (valid[beam]) {
                    delta[first + i] = now[beam] - before[beam];
                    both[first + i] = 1.0;
                }
            }
            for (Py_ssize_t s = tables[q]; s < tables[q + 1]; s++) dt[s] = since;
        }
        release(v, 4);
        if (failed) return -1;
    }
    return 0;
}

/* ---- pass 1 ---- */

/* pass1(points, offsets, tables, circle, changes, no_neighbour_jump, out, centres,
 *       max_motion, work, ys, xs, defer) -> number of turning angles t
 * points (K, 2); offsets (M + 1,) int64; tables (T + 1,) int64 (each table's first segment);
 * circle (T,) int64 (full circle); changes: None (no usable previous scan in the block) or
 * a list with, per table, None (no usable previous scan) or a tuple (beams (K_t,) int64,
 * ranges (N,) float64, previous ranges (N,) float64, previous valid (N,) bool, seconds
 * since the previous scan) for feature 14. Fills out (M, 14) but for features 8, 9 and 13 (pass2), the
 * centres (M, 2), max_motion (M,), work (M, 6) (the centred moments), and ys, xs (K + M,):
 * the turning angles' atan2 arguments at [0, t), the line fits' at [t, t + M). With defer
 * set, feature 3 (the medians) is left NaN for complete(). */
static PyObject *pass1(PyObject *self, PyObject *const *args, Py_ssize_t nargs) {
    (void)self;
    if (nargs != 13) {
        PyErr_SetString(PyExc_TypeError,
                        "pass1(points, offsets, tables, circle, changes, no_neighbour_jump, "
                        "out, centres, max_motion, work, ys, xs, defer)");
        return NULL;
    }
    Buf b[13];
    memset(b, 0, sizeof(b));
    Keyed *keyed = NULL;
    double *scratch = NULL, *delta = NULL, *both = NULL, *dt = NULL;
    PyObject *result = NULL;
    double no_jump = PyFloat_AsDouble(args[5]);
    if (no_jump == -1.0 && PyErr_Occurred()) return NULL;
    int defer = PyObject_IsTrue(args[12]);
    if (defer < 0) return NULL;
    if (take(args[0], &b[0], 0, 0, -1, "points") < 0) goto done;
    Py_ssize_t k = b[0].view.len / 16;
    if (k < 1 || b[0].view.len != 16 * k) {
        PyErr_SetString(PyExc_ValueError, "points: expected (K, 2) float64, K >= 1");
        goto done;
    }
    if (take(args[1], &b[1], 1, 0, -1, "offsets") < 0) goto done;
    Py_ssize_t m = b[1].view.len / 8 - 1;
    if (take(args[2], &b[2], 1, 0, -1, "tables") < 0) goto done;
    Py_ssize_t t_count = b[2].view.len / 8 - 1;
    if (take(args[3], &b[3], 1, 0, t_count, "circle") < 0) goto done;
    PyObject *changes = args[4];
    int speed = changes != Py_None;
    if (speed && (!PyList_CheckExact(changes) || PyList_GET_SIZE(changes) != t_count)) {
        PyErr_SetString(PyExc_ValueError, "changes: expected None or a list, one per table");
        goto done;
    }
    if (take(args[6], &b[7], 0, 1, m * N_FEATURES, "out") < 0 ||
        take(args[7], &b[8], 0, 1, 2 * m, "centres") < 0 ||
        take(args[8], &b[9], 0, 1, m, "max_motion") < 0 ||
        take(args[9], &b[10], 0, 1, m * N_WORK, "work") < 0 ||
        take(args[10], &b[11], 0, 1, k + m, "ys") < 0 ||
        take(args[11], &b[12], 0, 1, k + m, "xs") < 0)
        goto done;
    const double *P = b[0].view.buf;
    const long long *off = b[1].view.buf, *tables = b[2].view.buf, *circle = b[3].view.buf;
    double *out = b[7].view.buf, *centres = b[8].view.buf, *max_motion = b[9].view.buf;
    double *work = b[10].view.buf, *ys = b[11].view.buf, *xs = b[12].view.buf;
    if (m < 1 || off[0] != 0 || off[m] != k || t_count < 1 || tables[0] != 0 ||
        tables[t_count] != m) {
        PyErr_SetString(PyExc_ValueError, "offsets or tables do not cover the points");
        goto done;
    }
    Py_ssize_t longest = 0;
    for (Py_ssize_t s = 0; s < m; s++) {
        if (off[s + 1] <= off[s]) {
            PyErr_SetString(PyExc_ValueError, "a segment without points");
            goto done;
        }
        if (off[s + 1] - off[s] > longest) longest = off[s + 1] - off[s];
    }
    for (Py_ssize_t q = 0; q < t_count; q++)
        if (tables[q + 1] < tables[q]) {
            PyErr_SetString(PyExc_ValueError, "tables not in order");
            goto done;
        }
    if (speed) {
        delta = PyMem_Calloc((size_t)k, sizeof(double));
        both = PyMem_Calloc((size_t)k, sizeof(double));
        dt = PyMem_Malloc((size_t)m * sizeof(double));
        if (!delta || !both || !dt) {
            PyErr_NoMemory();
            goto done;
        }
        if (beam_changes(changes, off, tables, t_count, m, delta, both, dt) < 0) goto done;
    }
    keyed = PyMem_Malloc((size_t)longest * sizeof(Keyed));
    scratch = PyMem_Malloc((size_t)longest * 8 * sizeof(double));
    if (!keyed || !scratch) {
        PyErr_NoMemory();
        goto done;
    }
    double span = defer ? 0.0 : key_span(P, k);
    Py_ssize_t t = 0;
    for (Py_ssize_t s = 0; s < m; s++) {
        Py_ssize_t a = off[s], n = off[s + 1] - a;
        double nn = (double)n;
        const double *p = P + 2 * a;
        double *row = out + s * N_FEATURES, *w = work + s * N_WORK;
        double cx = reduce_sum(p, n, 2) / nn, cy = reduce_sum(p + 1, n, 2) / nn;
        centres[2 * s] = cx;
        centres[2 * s + 1] = cy;
        /* steps, curvature and turning angles, in point order */
        double *steps = scratch; /* steps[i]: into point i, i >= 1 */
        double length = 0.0, curvature = 0.0;
        for (Py_ssize_t i = 1; i < n; i++) {
            steps[i] = hypot(p[2 * i] - p[2 * i - 2], p[2 * i + 1] - p[2 * i - 1]);
            length += steps[i];
        }
        for (Py_ssize_t i = 1; i + 1 < n; i++) {
            double v1x = p[2 * i] - p[2 * i - 2], v1y = p[2 * i + 1] - p[2 * i - 1];
            double v2x = p[2 * i + 2] - p[2 * i], v2y = p[2 * i + 3] - p[2 * i + 1];
            double cross = v1x * v2y - v1y * v2x;
            double dot = v1x * v2x + v1y * v2y;
            double prod = steps[i] * steps[i + 1] * hypot(v1x + v2x, v1y + v2y);
            if (prod > 0.0) curvature += 2.0 * fabs(cross) / prod;
            ys[t] = cross;
            xs[t] = dot;
            t++;
        }
        /* the beams' range changes */
        double count = 0.0, total = 0.0, most = 0.0;
        if (speed) {
            for (Py_ssize_t i = a; i < a + n; i++) {
                count += both[i];
                total += delta[i];
                double d = fabs(delta[i]);
                if (d > most || isnan(d)) most = d;
            }
        }
        max_motion[s] = most;
        row[13] = speed && count > 0.0 ? total / (count > 1.0 ? count : 1.0) / dt[s] : 0.0;
        /* centred moments, pairwise */
        double *xx = scratch + n, *yy = xx + n, *xy = yy + n, *xz = xy + n, *yz = xz + n;
        double *z = yz + n;
        for (Py_ssize_t i = 0; i < n; i++) {
            double dx = p[2 * i] - cx, dy = p[2 * i + 1] - cy;
            xx[i] = dx * dx;
            yy[i] = dy * dy;
            xy[i] = dx * dy;
            z[i] = xx[i] + yy[i];
            xz[i] = dx * z[i];
            yz[i] = dy * z[i];
        }
        double sxx = reduce_sum(xx, n, 1), syy = reduce_sum(yy, n, 1);
        double sxy = reduce_sum(xy, n, 1);
        w[0] = sxx;
        w[1] = syy;
        w[2] = sxy;
        w[3] = reduce_sum(xz, n, 1);
        w[4] = reduce_sum(yz, n, 1);
        w[5] = reduce_sum(z, n, 1);
        /* squared deviations of the steps from their mean, in point order */
        double mean_step = n > 1 ? length / (nn - 1.0) : 0.0, ss = 0.0;
        for (Py_ssize_t i = 1; i < n; i++) {
            double d = steps[i] - mean_step;
            ss += d * d;
        }
        double inner = nn - 2.0 > 1.0 ? nn - 2.0 : 1.0;
        row[0] = nn;
        row[1] = n <= 1 ? 0.0 : sqrt((sxx + syy) / (nn - 1.0));
        /* 3: distances to the vector of medians */
        row[2] = defer ? NAN : mad_median(p, n, s, m, span, keyed, z + n);
        row[5] = hypot(p[2 * n - 2] - p[0], p[2 * n - 1] - p[1]);
        row[9] = length;
        row[10] = n < 3 ? 0.0 : sqrt(ss / (nn - 2.0));
        row[11] = curvature / inner;
        if (s > 0) { /* jump from the preceding segment's last point */
            double gap = hypot(p[0] - p[-2], p[1] - p[-1]);
            row[3] = gap;
            row[4 - N_FEATURES] = gap;
        }
        ys[k + s] = -2.0 * sxy; /* (placed at [t, t + M) below) */
        xs[k + s] = syy - sxx;
    }
    memmove(ys + t, ys + k, (size_t)m * sizeof(double));
    memmove(xs + t, xs + k, (size_t)m * sizeof(double));
    /* the first and last segment of each scan: its other end (full circle) or none */
    for (Py_ssize_t q = 0; q < t_count; q++) {
        Py_ssize_t first = tables[q], last = tables[q + 1] - 1;
        if (last < first) continue;
        if (circle[q] && last > first) {
            const double *f = P + 2 * off[first], *l = P + 2 * (off[last + 1] - 1);
            double closing = hypot(f[0] - l[0], f[1] - l[1]);
            out[first * N_FEATURES + 3] = closing;
            out[last * N_FEATURES + 4] = closing;
        } else {
            out[first * N_FEATURES + 3] = no_jump;
            out[last * N_FEATURES + 4] = no_jump;
        }
    }
    result = PyLong_FromSsize_t(t);
done:
    PyMem_Free(keyed);
    PyMem_Free(scratch);
    PyMem_Free(delta);
    PyMem_Free(both);
    PyMem_Free(dt);
    release(b, 13);
    return result;
}

/* ---- pass 2 ---- */

/* pass2(points, offsets, tables, flip, angles, no_circle_radius, out, centres, work,
 *       circle_centres, defer) -> None
 * angles (t + M,): numpy's arctan2 of pass1's ys, xs. Fills features 7, 8, 9 and 13 of out
 * and circle_centres (M, 2) (NaN without a circle); flips features 4, 5 and 13 of the
 * scans whose flip (T,) int64 is set (negative angle increment). With defer set, feature
 * 8 of the segments with a circle (their residuals) is left NaN for complete(). */
static PyObject *pass2(PyObject *self, PyObject *const *args, Py_ssize_t nargs) {
    (void)self;
    if (nargs != 11) {
        PyErr_SetString(PyExc_TypeError,
                        "pass2(points, offsets, tables, flip, angles, no_circle_radius, out, "
                        "centres, work, circle_centres, defer)");
        return NULL;
    }
    Buf b[9];
    memset(b, 0, sizeof(b));
    double *scratch = NULL;
    PyObject *result = NULL;
    double no_radius = PyFloat_AsDouble(args[5]);
    if (no_radius == -1.0 && PyErr_Occurred()) return NULL;
    int defer = PyObject_IsTrue(args[10]);
    if (defer < 0) return NULL;
    if (take(args[0], &b[0], 0, 0, -1, "points") < 0 ||
        take(args[1], &b[1], 1, 0, -1, "offsets") < 0 ||
        take(args[2], &b[2], 1, 0, -1, "tables") < 0)
        goto done;
    Py_ssize_t k = b[0].view.len / 16, m = b[1].view.len / 8 - 1;
    Py_ssize_t t_count = b[2].view.len / 8 - 1;
    if (take(args[3], &b[3], 1, 0, t_count, "flip") < 0 ||
        take(args[4], &b[4], 0, 0, -1, "angles") < 0 ||
        take(args[6], &b[5], 0, 1, m * N_FEATURES, "out") < 0 ||
        take(args[7], &b[6], 0, 0, 2 * m, "centres") < 0 ||
        take(args[8], &b[7], 0, 0, m * N_WORK, "work") < 0 ||
        take(args[9], &b[8], 0, 1, 2 * m, "circle_centres") < 0)
        goto done;
    const double *P = b[0].view.buf;
    const long long *off = b[1].view.buf, *tables = b[2].view.buf, *flip = b[3].view.buf;
    const double *ang = b[4].view.buf, *centres = b[6].view.buf, *work = b[7].view.buf;
    double *out = b[5].view.buf, *cc = b[8].view.buf;
    Py_ssize_t n_ang = b[4].view.len / 8;
    if (m < 1 || off[0] != 0 || off[m] != k || t_count < 1 || tables[0] != 0 ||
        tables[t_count] != m || n_ang < m) {
        PyErr_SetString(PyExc_ValueError, "offsets, tables or angles do not fit the points");
        goto done;
    }
    Py_ssize_t longest = 0, inner_total = 0;
    for (Py_ssize_t s = 0; s < m; s++) {
        Py_ssize_t n = off[s + 1] - off[s];
        if (n < 1) {
            PyErr_SetString(PyExc_ValueError, "a segment without points");
            goto done;
        }
        if (n > longest) longest = n;
        if (n > 2) inner_total += n - 2;
    }
    if (inner_total + m != n_ang) {
        PyErr_SetString(PyExc_ValueError, "angles: not one per interior point and segment");
        goto done;
    }
    scratch = PyMem_Malloc((size_t)longest * sizeof(double));
    if (!scratch) {
        PyErr_NoMemory();
        goto done;
    }
    const double *alphas = ang + inner_total;
    Py_ssize_t t = 0;
    for (Py_ssize_t s = 0; s < m; s++) {
        Py_ssize_t a = off[s], n = off[s + 1] - a;
        double nn = (double)n;
        const double *p = P + 2 * a, *w = work + s * N_WORK;
        double *row = out + s * N_FEATURES;
        double sxx = w[0], syy = w[1], sxy = w[2];
        double cx = centres[2 * s], cy = centres[2 * s + 1];
        /* 13: mean turning angle */
        double turning = 0.0;
        for (Py_ssize_t i = 1; i + 1 < n; i++) turning += ang[t++];
        double inner = nn - 2.0 > 1.0 ? nn - 2.0 : 1.0;
        row[12] = turning / inner;
        /* 7: linearity */
        double alpha = 0.5 * alphas[s];
        double ca = cos(alpha), sa = sin(alpha);
        double lin = sxx * ca * ca + 2.0 * sxy * ca * sa + syy * sa * sa;
        if (!isnan(lin) && !(lin > 0.0)) lin = 0.0; /* np.maximum(lin, 0.0) */
        row[6] = lin;
        /* 8, 9: algebraic circle fit */
        double xc, yc, rc;
        if (circle_fit(w, n, &xc, &yc, &rc)) {
            row[7] = defer ? NAN : circle_residual(p, n, cx, cy, xc, yc, rc, scratch);
            row[8] = rc;
            cc[2 * s] = cx + xc;
            cc[2 * s + 1] = cy + yc;
        } else {
            row[7] = lin;
            row[8] = no_radius;
            cc[2 * s] = NAN;
            cc[2 * s + 1] = NAN;
        }
    }
    /* 4, 5 and 13 by increasing angle */
    for (Py_ssize_t q = 0; q < t_count; q++) {
        if (!flip[q]) continue;
        for (Py_ssize_t s = tables[q]; s < tables[q + 1]; s++) {
            double *row = out + s * N_FEATURES;
            double jump = row[3];
            row[12] *= -1.0;
            row[3] = row[4];
            row[4] = jump;
        }
    }
    result = Py_None;
    Py_INCREF(result);
done:
    PyMem_Free(scratch);
    release(b, 9);
    return result;
}

/* ---- the deferred features ---- */

/* complete(points, offsets, rows, centres, work, out) -> None
 * Fills, for the segments rows (R,) int64, the features pass1 and pass2 left NaN with defer
 * set: 3 (the vector of medians) and 8 of the segments with a circle (the residuals), the
 * same floats as without defer (the medians' sort key spans all points, as there). */
static PyObject *complete(PyObject *self, PyObject *const *args, Py_ssize_t nargs) {
    (void)self;
    if (nargs != 6) {
        PyErr_SetString(PyExc_TypeError, "complete(points, offsets, rows, centres, work, out)");
        return NULL;
    }
    Buf b[6];
    memset(b, 0, sizeof(b));
    Keyed *keyed = NULL;
    double *scratch = NULL;
    PyObject *result = NULL;
    if (take(args[0], &b[0], 0, 0, -1, "points") < 0 ||
        take(args[1], &b[1], 1, 0, -1, "offsets") < 0 ||
        take(args[2], &b[2], 1, 0, -1, "rows") < 0)
        goto done;
    Py_ssize_t k = b[0].view.len / 16, m = b[1].view.len / 8 - 1, r = b[2].view.len / 8;
    if (take(args[3], &b[3], 0, 0, 2 * m, "centres") < 0 ||
        take(args[4], &b[4], 0, 0, m * N_WORK, "work") < 0 ||
        take(args[5], &b[5], 0, 1, m * N_FEATURES, "out") < 0)
        goto done;
    const double *P = b[0].view.buf, *centres = b[3].view.buf, *work = b[4].view.buf;
    const long long *off = b[1].view.buf, *rows = b[2].view.buf;
    double *out = b[5].view.buf;
    if (m < 1 || off[0] != 0 || off[m] != k) {
        PyErr_SetString(PyExc_ValueError, "offsets do not cover the points");
        goto done;
    }
    Py_ssize_t longest = 0;
    for (Py_ssize_t q = 0; q < r; q++) {
        if (rows[q] < 0 || rows[q] >= m || off[rows[q] + 1] <= off[rows[q]]) {
            PyErr_SetString(PyExc_ValueError, "a row outside the segments, or without points");
            goto done;
        }
        if (off[rows[q] + 1] - off[rows[q]] > longest) longest = off[rows[q] + 1] - off[rows[q]];
    }
    if (r == 0) {
        result = Py_None;
        Py_INCREF(result);
        goto done;
    }
    keyed = PyMem_Malloc((size_t)longest * sizeof(Keyed));
    scratch = PyMem_Malloc((size_t)longest * sizeof(double));
    if (!keyed || !scratch) {
        PyErr_NoMemory();
        goto done;
    }
    double span = key_span(P, k);
    for (Py_ssize_t q = 0; q < r; q++) {
        Py_ssize_t s = rows[q], a = off[s], n = off[s + 1] - a;
        const double *p = P + 2 * a;
        double *row = out + s * N_FEATURES;
        row[2] = mad_median(p, n, s, m, span, keyed, scratch);
        double xc, yc, rc;
        if (circle_fit(work + s * N_WORK, n, &xc, &yc, &rc))
            row[7] = circle_residual(p, n, centres[2 * s], centres[2 * s + 1], xc, yc, rc,
                                     scratch);
    }
    result = Py_None;
    Py_INCREF(result);
done:
    PyMem_Free(keyed);
    PyMem_Free(scratch);
    release(b, 6);
    return result;
}

/* ---- a scan's points ---- */

/* scan_points(ranges, range_min, range_max, cos, sin) -> (valid, points, beams, valid_points)
 * Scan's cached arrays of one scan of N beams (ranges, cos, sin (N,) float64): whether
 * each beam is valid (finite, above 0, within [range_min, range_max]; a bytearray of N
 * bools, as Scan.valid), the sensor-frame points (N, 2) with NaN rows for invalid beams (r
 * cos and r sin, one product each, as Scan._sensor_points), the valid beams' indices (K,)
 * int64 and their points (K, 2) (bytes). */
static PyObject *scan_points(PyObject *self, PyObject *const *args, Py_ssize_t nargs) {
    (void)self;
    if (nargs != 5) {
        PyErr_SetString(PyExc_TypeError, "scan_points(ranges, range_min, range_max, cos, sin)");
        return NULL;
    }
    Buf b[3];
    memset(b, 0, sizeof(b));
    PyObject *result = NULL, *parts[4] = {NULL, NULL, NULL, NULL};
    double lo = PyFloat_AsDouble(args[1]);
    if (lo == -1.0 && PyErr_Occurred()) return NULL;
    double hi = PyFloat_AsDouble(args[2]);
    if (hi == -1.0 && PyErr_Occurred()) return NULL;
    if (take(args[0], &b[0], 0, 0, -1, "ranges") < 0) goto done;
    Py_ssize_t n = b[0].view.len / 8;
    if (take(args[3], &b[1], 0, 0, n, "cos") < 0 || take(args[4], &b[2], 0, 0, n, "sin") < 0)
        goto done;
    const double *r = b[0].view.buf, *c = b[1].view.buf, *s = b[2].view.buf;
    parts[0] = PyByteArray_FromStringAndSize(NULL, n);
    parts[1] = PyBytes_FromStringAndSize(NULL, 16 * n);
    if (!parts[0] || !parts[1]) goto done;
    char *valid = PyByteArray_AS_STRING(parts[0]);
    double *points = (double *)PyBytes_AS_STRING(parts[1]);
    Py_ssize_t k = 0;
    for (Py_ssize_t i = 0; i < n; i++) {
        double x = r[i];
        valid[i] = (char)(isfinite(x) && x > 0.0 && x >= lo && x <= hi);
        k += valid[i];
        double v = valid[i] ? x : NAN;
        points[2 * i] = v * c[i];
        points[2 * i + 1] = v * s[i];
    }
    parts[2] = PyBytes_FromStringAndSize(NULL, 8 * k);
    parts[3] = PyBytes_FromStringAndSize(NULL, 16 * k);
    if (!parts[2] || !parts[3]) goto done;
    long long *beams = (long long *)PyBytes_AS_STRING(parts[2]);
    double *kept = (double *)PyBytes_AS_STRING(parts[3]);
    for (Py_ssize_t i = 0, j = 0; i < n; i++)
        if (valid[i]) {
            beams[j] = i;
            kept[2 * j] = points[2 * i];
            kept[2 * j + 1] = points[2 * i + 1];
            j++;
        }
    result = PyTuple_Pack(4, parts[0], parts[1], parts[2], parts[3]);
done:
    for (int i = 0; i < 4; i++) Py_XDECREF(parts[i]);
    release(b, 3);
    return result;
}

/* ---- segmentation ---- */

#define NEAR 1e-12 /* segmentation.NEAR */

/* whether the step from point i - 1 to point i of P is a jump: jumps' rule */
static inline int is_jump(const double *P, Py_ssize_t i, double threshold, int direct,
                          double limit) {
    double dx = P[2 * i] - P[2 * i - 2], dy = P[2 * i + 1] - P[2 * i - 1];
    if (direct) return hypot(dx, dy) >= threshold;
    double length = dx * dx + dy * dy;
    if (fabs(length - limit) <= NEAR * limit) return hypot(dx, dy) >= threshold;
    return length >= limit;
}

/* jumps(points, threshold, out) -> None
 * segmentation.at_least of the steps between neighbouring points (K, 2): out[i] (K - 1,)
 * bool, whether the step into point i + 1 is at least threshold long, as
 * np.hypot(dx, dy) >= threshold decides it (the same operations as at_least: the squared
 * length dx * dx + dy * dy against threshold * threshold, hypot within NEAR of it). */
static PyObject *jumps(PyObject *self, PyObject *const *args, Py_ssize_t nargs) {
    (void)self;
    if (nargs != 3) {
        PyErr_SetString(PyExc_TypeError, "jumps(points, threshold, out)");
        return NULL;
    }
    Buf b[2];
    memset(b, 0, sizeof(b));
    PyObject *result = NULL;
    double threshold = PyFloat_AsDouble(args[1]);
    if (threshold == -1.0 && PyErr_Occurred()) return NULL;
    if (take(args[0], &b[0], 0, 0, -1, "points") < 0) goto done;
    Py_ssize_t k = b[0].view.len / 16;
    if (k < 2 || b[0].view.len != 16 * k) {
        PyErr_SetString(PyExc_ValueError, "points: expected (K, 2) float64, K >= 2");
        goto done;
    }
    if (PyObject_GetBuffer(args[2], &b[1].view,
                           PyBUF_C_CONTIGUOUS | PyBUF_FORMAT | PyBUF_WRITABLE) < 0)
        goto done;
    b[1].held = 1;
    if (b[1].view.itemsize != 1 || !b[1].view.format || strcmp(b[1].view.format, "?") != 0 ||
        b[1].view.len != k - 1) {
        PyErr_Format(PyExc_ValueError, "out: expected %zd bool", k - 1);
        goto done;
    }
    const double *P = b[0].view.buf;
    char *out = b[1].view.buf;
    int direct = !(1e-150 < threshold && threshold < 1e150);
    double limit = threshold * threshold;
    for (Py_ssize_t i = 1; i < k; i++) out[i - 1] = (char)is_jump(P, i, threshold, direct, limit);
    result = Py_None;
    Py_INCREF(result);
done:
    release(b, 2);
    return result;
}

/* segment(points, beams, bounds, wrap, threshold) -> (offsets, table_starts, local, wrapped)
 * segmentation.segment_block's segments of T scans whose valid points (K, 2) and beams (K,)
 * int64 are joined, scan q's at rows [bounds[q], bounds[q + 1]) (bounds (T + 1,) int64):
 * a segment starts at every scan's first point and at every jump (is_jump, within the
 * scan); where wrap[q] (T,) int64 is set, the scan has more than one segment and its first
 * and last point lie closer than threshold (hypot, as segmentation._wrap), its last
 * segment's rows are moved in front of its first (points and beams reordered in place) and
 * the two are one. Returns, as bytes of int64: the M segments' first rows and K (M + 1),
 * each scan's first segment and M (T + 1), each scan's segments' first rows counted from
 * its own first row followed by its point count (M + T), and whether each scan wrapped
 * (T). (Bytes sized to the result: arrays of K entries allocated per block cost more than
 * the work, as glibc returns and maps their pages again.) */
static PyObject *segment(PyObject *self, PyObject *const *args, Py_ssize_t nargs) {
    (void)self;
    if (nargs != 5) {
        PyErr_SetString(PyExc_TypeError, "segment(points, beams, bounds, wrap, threshold)");
        return NULL;
    }
    Buf b[4];
    memset(b, 0, sizeof(b));
    PyObject *result = NULL, *parts[4] = {NULL, NULL, NULL, NULL};
    long long *offsets = NULL;
    double threshold = PyFloat_AsDouble(args[4]);
    if (threshold == -1.0 && PyErr_Occurred()) return NULL;
    if (take(args[0], &b[0], 0, 1, -1, "points") < 0) goto done;
    Py_ssize_t k = b[0].view.len / 16;
    if (b[0].view.len != 16 * k) {
        PyErr_SetString(PyExc_ValueError, "points: expected (K, 2) float64");
        goto done;
    }
    if (take(args[1], &b[1], 1, 1, k, "beams") < 0 ||
        take(args[2], &b[2], 1, 0, -1, "bounds") < 0)
        goto done;
    Py_ssize_t t = b[2].view.len / 8 - 1;
    if (t < 0 || take(args[3], &b[3], 1, 0, t, "wrap") < 0) goto done;
    double *P = b[0].view.buf;
    long long *beams = b[1].view.buf;
    const long long *bounds = b[2].view.buf, *wrap = b[3].view.buf;
    if (bounds[0] != 0 || bounds[t] != k) {
        PyErr_SetString(PyExc_ValueError, "bounds do not cover the points");
        goto done;
    }
    for (Py_ssize_t q = 0; q < t; q++)
        if (bounds[q + 1] < bounds[q]) {
            PyErr_SetString(PyExc_ValueError, "bounds do not increase");
            goto done;
        }
    int direct = !(1e-150 < threshold && threshold < 1e150);
    double limit = threshold * threshold;
    Py_ssize_t cap = 1024; /* (offsets grown as needed: most of a block's points are no start) */
    offsets = PyMem_Malloc((size_t)cap * sizeof(long long));
    parts[1] = PyBytes_FromStringAndSize(NULL, (t + 1) * 8);
    parts[3] = PyBytes_FromStringAndSize(NULL, (t > 0 ? t : 0) * 8);
    if (!offsets) PyErr_NoMemory();
    if (!offsets || !parts[1] || !parts[3]) goto done;
    long long *starts = (long long *)PyBytes_AS_STRING(parts[1]),
              *wrapped = (long long *)PyBytes_AS_STRING(parts[3]);
    Py_ssize_t m = 0;
    for (Py_ssize_t q = 0; q < t; q++) {
        Py_ssize_t a = bounds[q], e = bounds[q + 1], first = m;
        starts[q] = m;
        wrapped[q] = 0;
        for (Py_ssize_t i = a; i < e; i++) {
            if (i > a && !is_jump(P, i, threshold, direct, limit)) continue;
            if (m + 1 >= cap) { /* (room for this start and K after the last) */
                long long *more = PyMem_Realloc(offsets, (size_t)(2 * cap) * sizeof(long long));
                if (!more) {
                    PyErr_NoMemory();
                    goto done;
                }
                offsets = more;
                cap *= 2;
            }
            offsets[m++] = i;
        }
        if (wrap[q] && m - first > 1 &&
            hypot(P[2 * a] - P[2 * e - 2], P[2 * a + 1] - P[2 * e - 1]) < threshold) {
            Py_ssize_t last = offsets[m - 1], moved = e - last;
            /* rows [a, e) rotated left by last - a: three reversals */
            Py_ssize_t spans[3][2] = {{a, last - 1}, {last, e - 1}, {a, e - 1}};
            for (int r = 0; r < 3; r++)
                for (Py_ssize_t i = spans[r][0], j = spans[r][1]; i < j; i++, j--) {
                    double x = P[2 * i], y = P[2 * i + 1];
                    P[2 * i] = P[2 * j], P[2 * i + 1] = P[2 * j + 1];
                    P[2 * j] = x, P[2 * j + 1] = y;
                    long long c = beams[i];
                    beams[i] = beams[j], beams[j] = c;
                }
            /* the first segment continues the moved last one: the others shift by moved */
            for (Py_ssize_t s = first + 1; s < m - 1; s++) offsets[s] += moved;
            m--;
            wrapped[q] = 1;
        }
    }
    offsets[m] = k;
    starts[t] = m;
    parts[0] = PyBytes_FromStringAndSize((const char *)offsets, (m + 1) * 8);
    parts[2] = PyBytes_FromStringAndSize(NULL, (m + t) * 8);
    if (!parts[0] || !parts[2]) goto done;
    long long *local = (long long *)PyBytes_AS_STRING(parts[2]);
    Py_ssize_t at = 0;
    for (Py_ssize_t q = 0; q < t; q++) {
        for (Py_ssize_t s = starts[q]; s < starts[q + 1]; s++)
            local[at++] = offsets[s] - bounds[q];
        local[at++] = bounds[q + 1] - bounds[q];
    }
    result = PyTuple_Pack(4, parts[0], parts[1], parts[2], parts[3]);
done:
    for (int i = 0; i < 4; i++) Py_XDECREF(parts[i]);
    PyMem_Free(offsets);
    release(b, 4);
    return result;
}

/* ---- sparse legs ---- */

#define MIN_POINTS 3 /* features.MIN_POINTS: fewer points are no classifiable segment */

/* sparse(offsets, beams, points, table_starts, ranges, valid, increment, full, min_points,
 *        leg_width, jump_distance) -> bytes
 * sparse._sparse: the segments (offsets (M + 1,) into beams (K,) int64 and points (K, 2))
 * of T scans, scan q's from table_starts[q] (T + 1,), its ranges[q] (N_q,) float64 and
 * valid[q] (N_q,) bool (lists of T), its angle increment's magnitude increment[q] (T,)
 * [rad] and whether it covers the full circle full[q] (T,) int64. A segment of min_points
 * to MIN_POINTS - 1 points is a sparse leg where a leg_width leg at its mean end range gets
 * fewer than MIN_POINTS beams (leg_width / max(r |dtheta|, 1e-12), as expected_beams), its distinct readings
 * (two equal ranges count once) are at least min_points, its end points lie at most
 * leg_width apart (hypot), and each beam beside it (wrapping round a full circle) is
 * invalid, outside the scan or at least jump_distance farther. Returns their indices,
 * increasing, as bytes of int64. */
static PyObject *sparse(PyObject *self, PyObject *const *args, Py_ssize_t nargs) {
    (void)self;
    if (nargs != 11) {
        PyErr_SetString(PyExc_TypeError,
                        "sparse(offsets, beams, points, table_starts, ranges, valid, increment, "
                        "full, min_points, leg_width, jump_distance)");
        return NULL;
    }
    Buf b[6];
    memset(b, 0, sizeof(b));
    Buf *scan_bufs = NULL;
    Py_ssize_t t = 0;
    PyObject *result = NULL;
    long long *found = NULL;
    long min_points = PyLong_AsLong(args[8]);
    if (min_points == -1 && PyErr_Occurred()) return NULL;
    double leg_width = PyFloat_AsDouble(args[9]);
    if (leg_width == -1.0 && PyErr_Occurred()) return NULL;
    double jump_distance = PyFloat_AsDouble(args[10]);
    if (jump_distance == -1.0 && PyErr_Occurred()) return NULL;
    if (take(args[0], &b[0], 1, 0, -1, "offsets") < 0 ||
        take(args[1], &b[1], 1, 0, -1, "beams") < 0)
        goto done;
    Py_ssize_t m = b[0].view.len / 8 - 1, k = b[1].view.len / 8;
    if (take(args[2], &b[2], 0, 0, 2 * k, "points") < 0 ||
        take(args[3], &b[3], 1, 0, -1, "table_starts") < 0)
        goto done;
    t = b[3].view.len / 8 - 1;
    if (t < 0 || take(args[6], &b[4], 0, 0, t, "increment") < 0 ||
        take(args[7], &b[5], 1, 0, t, "full") < 0)
        goto done;
    const long long *off = b[0].view.buf, *beams = b[1].view.buf, *tables = b[3].view.buf,
                    *full = b[5].view.buf;
    const double *P = b[2].view.buf, *increment = b[4].view.buf;
    if (m < 0 || off[0] != 0 || off[m] != k || tables[0] != 0 || tables[t] != m) {
        PyErr_SetString(PyExc_ValueError, "offsets or table_starts do not cover the block");
        goto done;
    }
    if (!PyList_Check(args[4]) || !PyList_Check(args[5]) || PyList_GET_SIZE(args[4]) != t ||
        PyList_GET_SIZE(args[5]) != t) {
        PyErr_SetString(PyExc_ValueError, "ranges, valid: expected lists of one array a scan");
        goto done;
    }
    scan_bufs = PyMem_Calloc((size_t)(2 * t + 1), sizeof(Buf));
    found = PyMem_Malloc((size_t)(m + 1) * sizeof(long long));
    if (!scan_bufs || !found) {
        PyErr_NoMemory();
        goto done;
    }
    Py_ssize_t count = 0;
    for (Py_ssize_t q = 0; q < t; q++) {
        if (tables[q + 1] < tables[q]) {
            PyErr_SetString(PyExc_ValueError, "table_starts do not increase");
            goto done;
        }
        int taken = 0;
        for (Py_ssize_t i = tables[q]; i < tables[q + 1]; i++) {
            Py_ssize_t a = off[i], size = off[i + 1] - a;
            if (size < min_points || size >= MIN_POINTS) continue;
            if (!taken) { /* (the scan's arrays, once it has a candidate) */
                if (take(PyList_GET_ITEM(args[4], q), &scan_bufs[2 * q], 0, 0, -1, "ranges") < 0)
                    goto done;
                Py_ssize_t n = scan_bufs[2 * q].view.len / 8;
                if (take_bools(PyList_GET_ITEM(args[5], q), &scan_bufs[2 * q + 1], n, "valid") <
                    0)
                    goto done;
                taken = 1;
            }
            const double *ranges = scan_bufs[2 * q].view.buf;
            const char *valid = scan_bufs[2 * q + 1].view.buf;
            long long n = scan_bufs[2 * q].view.len / 8;
            long long first = beams[a], last = beams[a + size - 1];
            if (first < 0 || first >= n || last < 0 || last >= n) {
                PyErr_SetString(PyExc_ValueError, "a segment's beam outside its scan");
                goto done;
            }
            double r0 = ranges[first], r1 = ranges[last];
            double spacing = 0.5 * (r0 + r1) * increment[q];
            if (spacing < 1e-12) spacing = 1e-12; /* (NaN stays: np.maximum's, no leg) */
            if (!(leg_width / spacing < MIN_POINTS)) continue;
            int distinct = 1 + (size == 2) * (r0 != r1);
            if (distinct < min_points) continue;
            const double *p0 = P + 2 * a, *p1 = P + 2 * (a + size - 1);
            if (!(hypot(p1[0] - p0[0], p1[1] - p0[1]) <= leg_width)) continue;
            int ok = 1;
            for (int side = 0; side < 2 && ok; side++) {
                long long beam = side ? last + 1 : first - 1;
                double r = side ? r1 : r0;
                if (full[q]) beam = ((beam % n) + n) % n;
                int inside = beam >= 0 && beam < n;
                long long at = beam < 0 ? 0 : (beam > n - 1 ? n - 1 : beam);
                if (inside && valid[at] && !(ranges[at] - r >= jump_distance)) ok = 0;
            }
            if (ok) found[count++] = i;
        }
    }
    result = PyBytes_FromStringAndSize((const char *)found, count * 8);
done:
    if (scan_bufs) release(scan_bufs, (int)(2 * t));
    PyMem_Free(scan_bufs);
    PyMem_Free(found);
    release(b, 6);
    return result;
}

/* ---- AdaBoost ---- */

/* the number of grid values below x (left) or at most x (right), as np.searchsorted */
static Py_ssize_t rank_of(const double *grid, Py_ssize_t u, double x, int right) {
    Py_ssize_t lo = 0, hi = u;
    while (lo < hi) {
        Py_ssize_t mid = lo + (hi - lo) / 2;
        if (right ? grid[mid] <= x : grid[mid] < x)
            lo = mid + 1;
        else
            hi = mid;
    }
    return lo;
}

/* stump_sums(X, columns, group_column, right, grid, values, out) -> None
 * adaboost._StumpTables.evaluate: for each row of X (N, F) the groups' table values
 * (values (G, U + 1) at the rank of the row's value of feature columns[group_column[g]] in
 * grid (U,), counted on the right for the groups whose right (G,) bool is set) added in
 * group order, into out (N,). X must be finite (decision_function checks). */
static PyObject *stump_sums(PyObject *self, PyObject *const *args, Py_ssize_t nargs) {
    (void)self;
    if (nargs != 7) {
        PyErr_SetString(PyExc_TypeError,
                        "stump_sums(X, columns, group_column, right, grid, values, out)");
        return NULL;
    }
    Buf b[7];
    memset(b, 0, sizeof(b));
    PyObject *result = NULL;
    if (take(args[0], &b[0], 0, 0, -1, "X") < 0 || take(args[1], &b[1], 1, 0, -1, "columns") < 0 ||
        take(args[2], &b[2], 1, 0, -1, "group_column") < 0)
        goto done;
    Py_ssize_t g_count = b[2].view.len / 8, c_count = b[1].view.len / 8;
    if (take_bools(args[3], &b[3], g_count, "right") < 0 ||
        take(args[4], &b[4], 0, 0, -1, "grid") < 0)
        goto done;
    Py_ssize_t u = b[4].view.len / 8;
    if (take(args[5], &b[5], 0, 0, g_count * (u + 1), "values") < 0) goto done;
    if (b[0].view.ndim != 2) {
        PyErr_SetString(PyExc_ValueError, "X: expected (N, F) float64");
        goto done;
    }
    Py_ssize_t n = b[0].view.shape[0], f = b[0].view.shape[1];
    if (take(args[6], &b[6], 0, 1, n, "out") < 0) goto done;
    const double *X = b[0].view.buf, *grid = b[4].view.buf, *values = b[5].view.buf;
    const long long *columns = b[1].view.buf, *group_column = b[2].view.buf;
    const char *right = b[3].view.buf;
    double *out = b[6].view.buf;
    for (Py_ssize_t g = 0; g < g_count; g++)
        if (group_column[g] < 0 || group_column[g] >= c_count || columns[group_column[g]] < 0 ||
            columns[group_column[g]] >= f) {
            PyErr_SetString(PyExc_ValueError, "a stump's feature outside X");
            goto done;
        }
    if (g_count == 0) {
        PyErr_SetString(PyExc_ValueError, "no stumps");
        goto done;
    }
    for (Py_ssize_t i = 0; i < n; i++) {
        const double *row = X + i * f;
        double sum = 0.0, x = 0.0;
        long long column = -1;
        Py_ssize_t ranks[2] = {-1, -1}; /* of x, left and right (the groups of a feature
                                          follow each other: searched once per side) */
        for (Py_ssize_t g = 0; g < g_count; g++) {
            if (columns[group_column[g]] != column) {
                column = columns[group_column[g]];
                x = row[column];
                ranks[0] = ranks[1] = -1;
            }
            int side = right[g] ? 1 : 0;
            if (ranks[side] < 0) ranks[side] = rank_of(grid, u, x, side);
            double v = values[g * (u + 1) + ranks[side]];
            sum = g == 0 ? v : sum + v;
        }
        out[i] = sum;
    }
    result = Py_None;
    Py_INCREF(result);
done:
    release(b, 7);
    return result;
}

static PyMethodDef methods[] = {
    {"pass1", (PyCFunction)(void (*)(void))pass1, METH_FASTCALL,
     "pass1(points, offsets, tables, circle, changes, no_neighbour_jump, out, "
     "centres, max_motion, work, ys, xs, defer) -> t: the features but the line and circle fits "
     "and the turning angles, and the arguments of their atan2 (see the source)."},
    {"pass2", (PyCFunction)(void (*)(void))pass2, METH_FASTCALL,
     "pass2(points, offsets, tables, flip, angles, no_circle_radius, out, centres, work, "
     "circle_centres, defer): the line and circle fits and the turning angles from numpy's atan2."},
    {"complete", (PyCFunction)(void (*)(void))complete, METH_FASTCALL,
     "complete(points, offsets, rows, centres, work, out): the features pass1 and pass2 "
     "deferred (3, and 8 with a circle) of the segments rows."},
    {"jumps", (PyCFunction)(void (*)(void))jumps, METH_FASTCALL,
     "jumps(points, threshold, out): segmentation.at_least of the steps between "
     "neighbouring points into out."},
    {"scan_points", (PyCFunction)(void (*)(void))scan_points, METH_FASTCALL,
     "scan_points(ranges, range_min, range_max, cos, sin) -> (valid, points, beams, "
     "valid_points): a scan's validity and points (see the source)."},
    {"segment", (PyCFunction)(void (*)(void))segment, METH_FASTCALL,
     "segment(points, beams, bounds, wrap, threshold) -> (offsets, table_starts, local, "
     "wrapped): segmentation.segment_block's segments of a block of scans (see the source)."},
    {"sparse", (PyCFunction)(void (*)(void))sparse, METH_FASTCALL,
     "sparse(offsets, beams, points, table_starts, ranges, valid, increment, full, "
     "min_points, leg_width, jump_distance) -> bytes: sparse._sparse's sparse legs."},
    {"stump_sums", (PyCFunction)(void (*)(void))stump_sums, METH_FASTCALL,
     "stump_sums(X, columns, group_column, right, grid, values, out): "
     "adaboost._StumpTables.evaluate's margins into out."},
    {NULL, NULL, 0, NULL},
};

static struct PyModuleDef module = {
    PyModuleDef_HEAD_INIT, "_cfeatures",
    "The segment features of laserpeople.detection.features, compiled.", -1, methods,
    NULL, NULL, NULL, NULL,
};

PyMODINIT_FUNC PyInit__cfeatures(void) {
    PyObject *mod = PyModule_Create(&module);
    if (!mod) return NULL;
    if (PyModule_AddStringConstant(mod, "SOURCE_HASH", LP_SOURCE_HASH) < 0) {
        Py_DECREF(mod);
        return NULL;
    }
    return mod;
}
