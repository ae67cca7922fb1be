/* The constant-velocity Kalman steps of kalman.py for all track nodes of a scan at once,
 * compiled: the prediction and coasting of every live node (predict_and_coast), the gate
 * and likelihood terms of every (node, measurement) pair (mahalanobis_and_loglik,
 * euclidean_sq) and the Joseph-form updates of the kept children (update_batch).
 *
 * The same IEEE double operations in the same order as the numpy reference (build with
 * -ffp-contract=off: nothing is fused unless written as fma):
 *   - numpy's matrix products of these 4x4, 4x2 and 2x2 matrices are OpenBLAS's dgemm,
 *     which adds each element's products in order from 0.0 with fused multiply-adds
 *     (mm below, C's fma: the same floats on x86-64 with FMA, as measured);
 *   - np.einsum's sums of four products add them as (p0 + p2) + (p1 + p3), of two as
 *     p0 + p1, without fusing (dot4, dot2);
 *   - elementwise expressions in Python's order of evaluation. The cube of a step, the
 *     exponential decay of coasting and the logarithm of the likelihood are the
 *     reference's (numpy's power, exp and log are SIMD code on AVX-512 that differs from
 *     the C library's in the last bit): the caller passes the cubes and decays as its
 *     path computes them and takes the logarithm.
 *
 * C99, the CPython C API only (the buffer protocol for arrays). setup.py compiles the
 * checksum of this file and ../_cbuffers.h in as LP_SOURCE_HASH; kalman.py runs the numpy
 * reference when the files beside the module have another one.
 */
#define PY_SSIZE_T_CLEAN
#include <Python.h>

#include <math.h>
#include <string.h>

#include "../_cbuffers.h"

#ifndef LP_SOURCE_HASH
#define LP_SOURCE_HASH ""
#endif

/* The functions with products get a second version for x86-64 CPUs with FMA, chosen when
 * the module loads (GCC's target_clones): there C's fma is one instruction, elsewhere a
 * call into the C library (the same value, about ten times the time). */
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && defined(__linux__)
#define LP_FMA_CLONES __attribute__((target_clones("fma", "default")))
#else
#define LP_FMA_CLONES
#endif
/* (inlined into both versions of their callers: a call would run the default version) */
#if defined(__GNUC__)
#define LP_INLINE static inline __attribute__((always_inline))
#else
#define LP_INLINE static inline
#endif

/* c (n x m) = a (n x k) @ b (k x m), row-major: dgemm's sums, in order from 0.0, fused */
LP_INLINE void mm(const double *a, int n, int k, const double *b, int m, double *c) {
    /* (the sums of a row side by side: independent chains for the CPU to overlap) */
    for (int i = 0; i < n; i++) {
        double s[4] = {0.0, 0.0, 0.0, 0.0};
        for (int t = 0; t < k; t++) {
            double e = a[i * k + t];
            for (int j = 0; j < m; j++) s[j] = fma(e, b[t * m + j], s[j]);
        }
        for (int j = 0; j < m; j++) c[i * m + j] = s[j];
    }
}

/* the transpose bt (m x n) of b (n x m) */
LP_INLINE void transpose(const double *b, int n, int m, double *bt) {
    for (int i = 0; i < n; i++)
        for (int j = 0; j < m; j++) bt[j * n + i] = b[i * m + j];
}

/* c = f @ p @ f^T (4x4) */
LP_INLINE void sandwich(const double *f, const double *p, double *c) {
    double fp[16], ft[16];
    transpose(f, 4, 4, ft);
    mm(f, 4, 4, p, 4, fp);
    mm(fp, 4, 4, ft, 4, c);
}

/* c = f @ p @ f^T + q (4x4) */
LP_INLINE void sandwich_plus(const double *f, const double *p, const double *q, double *c) {
    sandwich(f, p, c);
    for (int i = 0; i < 16; i++) c[i] = c[i] + q[i];
}

/* np.einsum's sum of the products of four and of two pairs */
LP_INLINE double dot4(const double *a, const double *v) {
    return (a[0] * v[0] + a[2] * v[2]) + (a[1] * v[1] + a[3] * v[3]);
}

LP_INLINE double dot2(double a0, double v0, double a1, double v1) {
    return a0 * v0 + a1 * v1;
}

/* 16 or 4 doubles of the buffer of items[i] (a list) into out */
static int read_rows(PyObject *items, Py_ssize_t i, Py_ssize_t count, double *out,
                     const char *name) {
    Buf b;
    memset(&b, 0, sizeof b);
    if (take(PyList_GET_ITEM(items, i), &b, 0, 0, count, name) < 0) {
        release(&b, 1);
        return -1;
    }
    memcpy(out, b.view.buf, (size_t)count * sizeof(double));
    release(&b, 1);
    return 0;
}

static int check_list(PyObject *obj, Py_ssize_t n, const char *name) {
    if (!PyList_CheckExact(obj) || PyList_GET_SIZE(obj) != n) {
        PyErr_Format(PyExc_ValueError, "%s: expected a list of %zd", name, n);
        return -1;
    }
    return 0;
}

/* One node's prediction: the state x (4) and covariance p (16) over the step d [s] (its
 * cube d3) with the process noise of accel_psd a: mean pm (4), covariance pc (16); and,
 * where cm is not NULL, coasting with the velocity decaying by k (g = tau (1 - k)):
 * cm (4), cc (16). */
static LP_FMA_CLONES void predict_node(const double *x, const double *p, double d, double d3,
                                       double a, double tau, double k, double *pm,
                                       double *pc, double *cm, double *cc) {
    /* kalman.process_noise and transition (as _step_matrices builds them) */
    double pp = a * d3 / 3.0, pv = a * (d * d) / 2.0, vv = a * d;
    double q[16] = {pp, 0.0, pv, 0.0, 0.0, pp, 0.0, pv, pv, 0.0, vv, 0.0, 0.0, pv, 0.0, vv};
    double f[16] = {1.0, 0.0, d, 0.0, 0.0, 1.0, 0.0, d, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0};
    pm[0] = x[0] + x[2] * d;
    pm[1] = x[1] + x[3] * d;
    pm[2] = x[2];
    pm[3] = x[3];
    sandwich_plus(f, p, q, pc);
    if (!cm) return;
    /* kalman._coast: velocity decaying by k, position gaining g = tau (1 - k) of it */
    double g = tau * (1.0 - k);
    double fc[16] = {1.0, 0.0, g, 0.0, 0.0, 1.0, 0.0, g, 0.0, 0.0, k, 0.0, 0.0, 0.0, 0.0, k};
    for (int r = 0; r < 4; r++) cm[r] = dot4(fc + 4 * r, x);
    sandwich_plus(fc, p, q, cc);
}

/* predict(means, covs, dts, cubes, decays, accel_psd, tau, pm, pc, cm, cc):
 * kalman.predict_and_coast of N nodes. means and covs are lists of N arrays of 4 and 16
 * doubles or arrays (N, 4) and (N, 4, 4), dts a list of N steps [s], cubes their dt**3 (as the reference's path computes
 * them: by the C library's pow or numpy's), decays a list of N exp(-dt / tau) (numpy's) or
 * None (tau infinite: cm and cc are not written and may be None); pm (N, 4), pc (N, 4, 4),
 * cm, cc float64 out. */
static PyObject *predict(PyObject *self, PyObject *const *args, Py_ssize_t nargs) {
    (void)self;
    if (nargs != 11) {
        PyErr_SetString(PyExc_TypeError, "predict takes 11 arguments");
        return NULL;
    }
    PyObject *means = args[0], *covs = args[1], *dts = args[2], *cubes = args[3];
    PyObject *decays = args[4];
    if (!PyList_CheckExact(dts)) {
        PyErr_SetString(PyExc_ValueError, "dts: expected a list");
        return NULL;
    }
    Py_ssize_t n = PyList_GET_SIZE(dts);
    int coasting = decays != Py_None, rows = PyList_CheckExact(means);
    if ((rows && (check_list(means, n, "means") < 0 || check_list(covs, n, "covs") < 0)) ||
        check_list(cubes, n, "cubes") < 0 || (coasting && check_list(decays, n, "decays") < 0))
        return NULL;
    double a = PyFloat_AsDouble(args[5]);
    if (a == -1.0 && PyErr_Occurred()) return NULL;
    double tau = PyFloat_AsDouble(args[6]);
    if (tau == -1.0 && PyErr_Occurred()) return NULL;
    Buf b[6];
    memset(b, 0, sizeof b);
    PyObject *result = NULL;
    if (take(args[7], &b[0], 0, 1, 4 * n, "pm") < 0 ||
        take(args[8], &b[1], 0, 1, 16 * n, "pc") < 0)
        goto done;
    if (!rows && (take(means, &b[4], 0, 0, 4 * n, "means") < 0 ||
                  take(covs, &b[5], 0, 0, 16 * n, "covs") < 0))
        goto done;
    if (coasting && (take(args[9], &b[2], 0, 1, 4 * n, "cm") < 0 ||
                     take(args[10], &b[3], 0, 1, 16 * n, "cc") < 0))
        goto done;
    double *pm = b[0].view.buf, *pc = b[1].view.buf;
    for (Py_ssize_t i = 0; i < n; i++) {
        double x[4], p[16];
        if (!rows) {
            memcpy(x, (double *)b[4].view.buf + 4 * i, sizeof x);
            memcpy(p, (double *)b[5].view.buf + 16 * i, sizeof p);
        } else if (read_rows(means, i, 4, x, "means") < 0 ||
                   read_rows(covs, i, 16, p, "covs") < 0)
            goto done;
        double d = PyFloat_AsDouble(PyList_GET_ITEM(dts, i));
        if (d == -1.0 && PyErr_Occurred()) goto done;
        double d3 = PyFloat_AsDouble(PyList_GET_ITEM(cubes, i));
        if (d3 == -1.0 && PyErr_Occurred()) goto done;
        double k = 1.0;
        if (coasting) {
            k = PyFloat_AsDouble(PyList_GET_ITEM(decays, i));
            if (k == -1.0 && PyErr_Occurred()) goto done;
        }
        predict_node(x, p, d, d3, a, coasting ? tau : 0.0, k, pm + 4 * i, pc + 16 * i,
                     coasting ? (double *)b[2].view.buf + 4 * i : NULL,
                     coasting ? (double *)b[3].view.buf + 16 * i : NULL);
    }
    result = Py_None;
    Py_INCREF(result);
done:
    release(b, 6);
    return result;
}

/* score(pm, pc, z, r, gate, max_gate_sq, log_2pi, gated, partial, det, d2): the gate and likelihood
 * terms of every (node, measurement) pair of N predicted nodes, pm (N, 4) and pc (N, 4, 4),
 * and M measurements, z (M, 2) and r (M, 2, 2): gated (N, M) bool out, whether the squared
 * Mahalanobis distance is within gate and the squared distance within max_gate_sq
 * (kalman.mahalanobis_and_loglik, euclidean_sq); partial (N, M) out, -0.5 d2 - log_2pi,
 * det (N, M) out, det S, whose logarithm the caller takes (loglik = partial - 0.5
 * log(det)), and d2 (N, M) out, the squared Mahalanobis distances; gated and d2 may be None
 * (not written). */
static PyObject *score(PyObject *self, PyObject *const *args, Py_ssize_t nargs) {
    (void)self;
    if (nargs != 11) {
        PyErr_SetString(PyExc_TypeError, "score takes 11 arguments");
        return NULL;
    }
    double gate = PyFloat_AsDouble(args[4]);
    if (gate == -1.0 && PyErr_Occurred()) return NULL;
    double max_sq = PyFloat_AsDouble(args[5]);
    if (max_sq == -1.0 && PyErr_Occurred()) return NULL;
    double log_2pi = PyFloat_AsDouble(args[6]);
    if (log_2pi == -1.0 && PyErr_Occurred()) return NULL;
    Buf b[8];
    memset(b, 0, sizeof b);
    PyObject *result = NULL;
    if (take(args[0], &b[0], 0, 0, -1, "pm") < 0 || take(args[2], &b[2], 0, 0, -1, "z") < 0)
        goto done;
    Py_ssize_t n = b[0].view.len / 32, m = b[2].view.len / 16;
    if (take(args[1], &b[1], 0, 0, 16 * n, "pc") < 0 ||
        take(args[3], &b[3], 0, 0, 4 * m, "r") < 0 ||
        (args[7] != Py_None && take_bools(args[7], &b[4], n * m, "gated") < 0) ||
        take(args[8], &b[5], 0, 1, n * m, "partial") < 0 ||
        take(args[9], &b[6], 0, 1, n * m, "det") < 0 ||
        (args[10] != Py_None && take(args[10], &b[7], 0, 1, n * m, "d2") < 0))
        goto done;
    const double *pm = b[0].view.buf, *pc = b[1].view.buf, *z = b[2].view.buf;
    const double *r = b[3].view.buf;
    char *gated = b[4].held ? b[4].view.buf : NULL;
    double *partial = b[5].view.buf, *dets = b[6].view.buf;
    double *d2s = b[7].held ? b[7].view.buf : NULL;
    for (Py_ssize_t i = 0; i < n; i++) {
        double mx = pm[4 * i], my = pm[4 * i + 1];
        const double *p = pc + 16 * i;
        for (Py_ssize_t j = 0; j < m; j++) {
            const double *rj = r + 4 * j;
            double sa = p[0] + rj[0], sb = p[1] + rj[1], sd = p[5] + rj[3];
            double det = sa * sd - sb * sb;
            double vx = z[2 * j] - mx, vy = z[2 * j + 1] - my;
            double d2 = (sd * vx * vx - 2.0 * sb * vx * vy + sa * vy * vy) / det;
            Py_ssize_t at = i * m + j;
            if (gated) gated[at] = (char)(d2 <= gate && dot2(vx, vx, vy, vy) <= max_sq);
            if (d2s) d2s[at] = d2;
            partial[at] = -0.5 * d2 - log_2pi;
            dets[at] = det;
        }
    }
    result = Py_None;
    Py_INCREF(result);
done:
    release(b, 8);
    return result;
}

/* read the index items[i] (a list of ints) in [0, n) */
static int read_index(PyObject *items, Py_ssize_t i, Py_ssize_t n, Py_ssize_t *out,
                      const char *name) {
    Py_ssize_t v = PyLong_AsSsize_t(PyList_GET_ITEM(items, i));
    if (v == -1 && PyErr_Occurred()) return -1;
    if (v < 0 || v >= n) {
        PyErr_Format(PyExc_IndexError, "%s: %zd out of [0, %zd)", name, v, n);
        return -1;
    }
    *out = v;
    return 0;
}

/* One Kalman update (kalman.update_batch, Joseph form): the predicted state x (4) and
 * covariance p (16) with the measurement z (2), covariance rj (4): mean (4), c (16). */
static LP_FMA_CLONES void update_one(const double *x, const double *p, const double *z,
                                     const double *rj, double *mean, double *c) {
    /* S^-1 (as _few_update), K = P H^T S^-1 */
    double sa = p[0] + rj[0], sb = p[1] + rj[1], sc = p[4] + rj[2], sd = p[5] + rj[3];
    double det = sa * sd - sb * sc;
    double inv[4] = {sd / det, -sb / det, -sc / det, sa / det};
    double ph[8], gain[8], gt[8];
    for (int row = 0; row < 4; row++) {
        ph[2 * row] = p[4 * row];
        ph[2 * row + 1] = p[4 * row + 1];
    }
    mm(ph, 4, 2, inv, 2, gain);
    double vx = z[0] - x[0], vy = z[1] - x[1];
    for (int row = 0; row < 4; row++)
        mean[row] = x[row] + dot2(gain[2 * row], vx, gain[2 * row + 1], vy);
    /* Joseph form: (I - K H) P (I - K H)^T + K R K^T, symmetrised */
    double ikh[16] = {1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0,
                      0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0};
    for (int row = 0; row < 4; row++) {
        ikh[4 * row] = ikh[4 * row] - gain[2 * row];
        ikh[4 * row + 1] = ikh[4 * row + 1] - gain[2 * row + 1];
    }
    double joseph[16], kr[8], krk[16];
    sandwich(ikh, p, joseph);
    mm(gain, 4, 2, rj, 2, kr);
    transpose(gain, 4, 2, gt);
    mm(kr, 4, 2, gt, 4, krk);
    double sum[16];
    for (int e = 0; e < 16; e++) sum[e] = joseph[e] + krk[e];
    for (int row = 0; row < 4; row++)
        for (int col = 0; col < 4; col++)
            c[4 * row + col] = 0.5 * (sum[4 * row + col] + sum[4 * col + row]);
}

/* update(pm, pc, rows, z, r, js, means, covs): kalman.update_batch of K states, the rows
 * `rows` (a list of K ints) of pm (N, 4) and pc (N, 4, 4), with the measurements `js` (a
 * list of K ints) of z (M, 2) and r (M, 2, 2); means (K, 4) and covs (K, 4, 4) out. */
static PyObject *update(PyObject *self, PyObject *const *args, Py_ssize_t nargs) {
    (void)self;
    if (nargs != 8) {
        PyErr_SetString(PyExc_TypeError, "update takes 8 arguments");
        return NULL;
    }
    PyObject *rows = args[2], *js = args[5];
    if (!PyList_CheckExact(rows)) {
        PyErr_SetString(PyExc_ValueError, "rows: expected a list");
        return NULL;
    }
    Py_ssize_t k = PyList_GET_SIZE(rows);
    if (check_list(js, k, "js") < 0) return NULL;
    Buf b[6];
    memset(b, 0, sizeof b);
    PyObject *result = NULL;
    if (take(args[0], &b[0], 0, 0, -1, "pm") < 0 || take(args[3], &b[2], 0, 0, -1, "z") < 0)
        goto done;
    Py_ssize_t n = b[0].view.len / 32, m = b[2].view.len / 16;
    if (take(args[1], &b[1], 0, 0, 16 * n, "pc") < 0 ||
        take(args[4], &b[3], 0, 0, 4 * m, "r") < 0 ||
        take(args[6], &b[4], 0, 1, 4 * k, "means") < 0 ||
        take(args[7], &b[5], 0, 1, 16 * k, "covs") < 0)
        goto done;
    const double *pm = b[0].view.buf, *pc = b[1].view.buf, *z = b[2].view.buf;
    const double *r = b[3].view.buf;
    double *out_m = b[4].view.buf, *out_c = b[5].view.buf;
    for (Py_ssize_t t = 0; t < k; t++) {
        Py_ssize_t i, j;
        if (read_index(rows, t, n, &i, "rows") < 0 || read_index(js, t, m, &j, "js") < 0)
            goto done;
        update_one(pm + 4 * i, pc + 16 * i, z + 2 * j, r + 4 * j, out_m + 4 * t,
                   out_c + 16 * t);
    }
    result = Py_None;
    Py_INCREF(result);
done:
    release(b, 6);
    return result;
}

static PyMethodDef methods[] = {
    {"predict", (PyCFunction)(void (*)(void))predict, METH_FASTCALL,
     "predict(means, covs, dts, cubes, decays, accel_psd, tau, pm, pc, cm, cc): "
     "kalman.predict_and_coast of the nodes into pm, pc (and cm, cc)."},
    {"score", (PyCFunction)(void (*)(void))score, METH_FASTCALL,
     "score(pm, pc, z, r, gate, max_gate_sq, log_2pi, gated, partial, det, d2): the gate, "
     "-0.5 d2 - log_2pi, det S and d2 of every (node, measurement) pair."},
    {"update", (PyCFunction)(void (*)(void))update, METH_FASTCALL,
     "update(pm, pc, rows, z, r, js, means, covs): kalman.update_batch of the rows "
     "with the measurements js into means, covs."},
    {NULL, NULL, 0, NULL},
};

static struct PyModuleDef module = {
    PyModuleDef_HEAD_INIT, "_ckalman",
    "The Kalman steps of laserpeople.tracking.kalman for all nodes of a scan, compiled.", -1,
    methods, NULL, NULL, NULL, NULL,
};

PyMODINIT_FUNC PyInit__ckalman(void) {
    PyObject *mod = PyModule_Create(&module);
    if (!mod) return NULL;
    if (PyModule_AddStringConstant(mod, "SOURCE_HASH", LP_SOURCE_HASH) < 0) {
        Py_DECREF(mod);
        return NULL;
    }
    return mod;
}
