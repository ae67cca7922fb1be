/* The leg MHT's depth-first listing of a cluster's k best children, compiled.
 *
 * The same algorithm as listing.py's list_children (_Lister, _BudgetedLister): the same
 * choices in the same order, the same bounds summed in the same order of IEEE double
 * operations (build with -ffp-contract=off: no fused multiply-add), the same cuts, steps
 * and children; Python lists and floats are read directly (no arrays). Clusters that
 * list_children hands to single_children (the shortcut) and calls with a NaN prior or
 * k < 1 return NotImplemented: the Python listing takes them.
 *
 * C99, the CPython C API only. setup.py compiles this file's checksum in as LP_SOURCE_HASH;
 * compiled.py runs the Python listing when the file beside the module has another one.
 */
#define PY_SSIZE_T_CLEAN
#include <Python.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

#ifndef LP_SOURCE_HASH
#define LP_SOURCE_HASH ""
#endif

/* labels (probability.py) */
enum { DETECTED = 0, OCCLUDED = 1, DELETED = 2 };
enum { MATCHED = 0, NEW_LABEL = 1, FALSE_ALARM = 2 };
#define MAX_M 30 /* measurement bit masks fit an unsigned int */

static PyObject *labelled_assignment = NULL; /* matrix.LabelledAssignment, set by setup() */
static int max_listed = 10;                  /* listing.MAX_LISTED_MEASUREMENTS */

typedef struct {
    double cost;
    int label;
    int meas; /* measurement or -1 */
    unsigned bit;
} Choice;

typedef struct {
    double cost;
    int label;
} MeasChoice;

typedef struct {
    double total;
    Py_ssize_t order;
    Py_ssize_t parent;
    Py_ssize_t depth;
    Py_ssize_t at; /* offset into the int arena: labels, measurements, free labels */
    unsigned used;
} Found;

typedef struct {
    /* tables */
    Choice **choices; /* per node, its choices, cheapest first */
    int *n_choices;
    double *cheapest;
    unsigned *gates;
    MeasChoice meas_choices[MAX_M][2];
    int n_meas_choices[MAX_M];
    double meas_min[MAX_M];
    double *unmatched_lb;
    double *maybe_lb;
    Py_ssize_t k;
    double max_gap;
    int m;
    unsigned full;
    /* state */
    Found *found;
    Py_ssize_t n_found, cap_found;
    int *arena;
    Py_ssize_t n_arena, cap_arena;
    double best, limit, kth;
    double *kept; /* max-heap of the k best totals */
    Py_ssize_t n_kept;
    int free_labels[MAX_M];
    int budgeted;
    long long left;
    int out_of_steps;
    int no_memory;
    /* the parent being listed */
    Py_ssize_t pi;
    const Py_ssize_t *rows;
    Py_ssize_t depth;
    double *suffix;
    unsigned *reach;
    int *labels;
    int *meas;
} Lister;

static int choice_less(const Choice *a, const Choice *b) {
    /* Python's tuple order (cost, label, measurement, bit); costs are finite or -inf */
    if (a->cost != b->cost) return a->cost < b->cost;
    if (a->label != b->label) return a->label < b->label;
    return a->meas < b->meas;
}

static void sort_choices(Choice *ch, int n) {
    for (int i = 1; i < n; i++) {
        Choice x = ch[i];
        int j = i - 1;
        while (j >= 0 && choice_less(&x, &ch[j])) {
            ch[j + 1] = ch[j];
            j--;
        }
        ch[j + 1] = x;
    }
}

static void heap_push(double *h, Py_ssize_t *n, double v) {
    Py_ssize_t i = (*n)++;
    while (i > 0) {
        Py_ssize_t p = (i - 1) / 2;
        if (!(h[p] < v)) break;
        h[i] = h[p];
        i = p;
    }
    h[i] = v;
}

static void heap_replace_top(double *h, Py_ssize_t n, double v) {
    Py_ssize_t i = 0;
    for (;;) {
        Py_ssize_t l = 2 * i + 1, r = l + 1, big = i;
        double bv = v;
        if (l < n && h[l] > bv) {
            big = l;
            bv = h[l];
        }
        if (r < n && h[r] > bv) big = r;
        if (big == i) break;
        h[i] = h[big];
        i = big;
    }
    h[i] = v;
}

static void record(Lister *L, double total, unsigned used) {
    if (L->n_found == L->cap_found) {
        Py_ssize_t cap = L->cap_found ? 2 * L->cap_found : 64;
        Found *f = (Found *)PyMem_Realloc(L->found, (size_t)cap * sizeof(Found));
        if (!f) {
            L->no_memory = 1;
            return;
        }
        L->found = f;
        L->cap_found = cap;
    }
    Py_ssize_t need = 2 * L->depth + L->m;
    if (L->n_arena + need > L->cap_arena) {
        Py_ssize_t cap = L->cap_arena ? 2 * L->cap_arena : 256;
        while (cap < L->n_arena + need) cap *= 2;
        int *a = (int *)PyMem_Realloc(L->arena, (size_t)cap * sizeof(int));
        if (!a) {
            L->no_memory = 1;
            return;
        }
        L->arena = a;
        L->cap_arena = cap;
    }
    Found *f = &L->found[L->n_found];
    f->total = total;
    f->order = L->n_found;
    f->parent = L->pi;
    f->depth = L->depth;
    f->at = L->n_arena;
    f->used = used;
    int *a = L->arena + L->n_arena;
    memcpy(a, L->labels, (size_t)L->depth * sizeof(int));
    memcpy(a + L->depth, L->meas, (size_t)L->depth * sizeof(int));
    memcpy(a + 2 * L->depth, L->free_labels, (size_t)L->m * sizeof(int));
    L->n_arena += need;
    L->n_found++;
    if (total < L->best) {
        L->best = total;
        L->limit = total + L->max_gap;
    }
    if (L->n_kept < L->k) {
        heap_push(L->kept, &L->n_kept, total);
        if (L->n_kept == L->k) L->kth = L->kept[0];
    } else if (total < L->kept[0]) {
        heap_replace_top(L->kept, L->n_kept, total);
        L->kth = L->kept[0];
    }
}

static int take_step(Lister *L) {
    if (L->budgeted && --L->left < 0) {
        L->out_of_steps = 1;
        return 0;
    }
    return 1;
}

static void measurements(Lister *L, int j, double cost, unsigned used, double rest_lb) {
    if (!take_step(L)) return;
    int m = L->m;
    while (j < m && (used >> j & 1u)) j++;
    if (j == m) {
        record(L, cost, used);
        return;
    }
    double rest = rest_lb - L->meas_min[j];
    for (int c = 0; c < L->n_meas_choices[j]; c++) {
        double cc = L->meas_choices[j][c].cost;
        double bound = cost + cc + rest;
        if (bound > L->limit || bound >= L->kth) break;
        L->free_labels[j] = L->meas_choices[j][c].label;
        measurements(L, j + 1, cost + cc, used, rest);
        if (L->out_of_steps || L->no_memory) return;
    }
}

static void tracks_at(Lister *L, Py_ssize_t t, double cost, unsigned used) {
    if (!take_step(L)) return;
    unsigned full = L->full;
    double suffix = L->suffix[t + 1];
    unsigned reach = L->reach[t + 1];
    int last = t + 1 == L->depth;
    Py_ssize_t node = L->rows[t];
    const Choice *ch = L->choices[node];
    int n = L->n_choices[node];
    for (int c = 0; c < n; c++) {
        if (used & ch[c].bit) continue;
        unsigned child_used = used | ch[c].bit;
        double child_cost = cost + ch[c].cost;
        unsigned free = full & ~child_used;
        double bound = child_cost + suffix + L->unmatched_lb[free & ~reach] +
                       L->maybe_lb[free & reach];
        if (bound > L->limit || bound >= L->kth) continue;
        L->labels[t] = ch[c].label;
        L->meas[t] = ch[c].meas;
        if (!last)
            tracks_at(L, t + 1, child_cost, child_used);
        else if (child_used == full)
            record(L, child_cost, child_used);
        else
            measurements(L, 0, child_cost, child_used, L->unmatched_lb[free]);
        if (L->out_of_steps || L->no_memory) return;
    }
}

static void list_parent(Lister *L, Py_ssize_t pi, double prior, const Py_ssize_t *rows,
                        Py_ssize_t depth) {
    double *suffix = L->suffix;
    unsigned *reach = L->reach;
    suffix[depth] = 0.0;
    reach[depth] = 0;
    for (Py_ssize_t t = depth - 1; t >= 0; t--) {
        suffix[t] = suffix[t + 1] + L->cheapest[rows[t]];
        reach[t] = reach[t + 1] | L->gates[rows[t]];
    }
    L->pi = pi;
    L->rows = rows;
    L->depth = depth;
    unsigned full = L->full;
    double bound = prior + suffix[0] + L->unmatched_lb[full & ~reach[0]] +
                   L->maybe_lb[full & reach[0]];
    if (bound > L->limit || bound >= L->kth) return;
    if (depth)
        tracks_at(L, 0, prior, 0);
    else
        measurements(L, 0, prior, 0, L->unmatched_lb[full]);
}

/* --- reading Python values ---------------------------------------------------------- */

static int read_doubles(PyObject *seq, double *out, Py_ssize_t n, const char *what) {
    PyObject *fast = PySequence_Fast(seq, what);
    if (!fast) return -1;
    if (PySequence_Fast_GET_SIZE(fast) != n) {
        PyErr_Format(PyExc_ValueError, "%s: %zd values, expected %zd", what,
                     PySequence_Fast_GET_SIZE(fast), n);
        Py_DECREF(fast);
        return -1;
    }
    PyObject **items = PySequence_Fast_ITEMS(fast);
    for (Py_ssize_t i = 0; i < n; i++) {
        double v = PyFloat_AsDouble(items[i]);
        if (v == -1.0 && PyErr_Occurred()) {
            Py_DECREF(fast);
            return -1;
        }
        out[i] = v;
    }
    Py_DECREF(fast);
    return 0;
}

static int found_cmp(const void *pa, const void *pb) {
    const Found *a = (const Found *)pa, *b = (const Found *)pb;
    if (a->total < b->total) return -1;
    if (a->total > b->total) return 1;
    return (a->order > b->order) - (a->order < b->order);
}

/* a stable sort by total (Python's list.sort with key=total): merge sort on Found */
static int sort_found(Found *f, Py_ssize_t n) {
    int sorted = 1;
    for (Py_ssize_t i = 1; i < n && sorted; i++) sorted = !(f[i].total < f[i - 1].total);
    if (sorted) return 0;
    for (Py_ssize_t i = 0; i < n; i++)
        if (isnan(f[i].total)) return -1; /* (no total order: Python's sort decides) */
    qsort(f, (size_t)n, sizeof(Found), found_cmp);
    return 0;
}

static PyObject *int_list(const int *v, Py_ssize_t n) {
    PyObject *out = PyList_New(n);
    if (!out) return NULL;
    for (Py_ssize_t i = 0; i < n; i++) {
        PyObject *x = PyLong_FromLong(v[i]);
        if (!x) {
            Py_DECREF(out);
            return NULL;
        }
        PyList_SET_ITEM(out, i, x);
    }
    return out;
}

static PyObject *int_tuple(const int *v, Py_ssize_t n) {
    PyObject *out = PyTuple_New(n);
    if (!out) return NULL;
    for (Py_ssize_t i = 0; i < n; i++) {
        PyObject *x = PyLong_FromLong(v[i]);
        if (!x) {
            Py_DECREF(out);
            return NULL;
        }
        PyTuple_SET_ITEM(out, i, x);
    }
    return out;
}

/* the number of children of the parents (an upper bound), saturated above cap */
static unsigned long long children_bound(Py_ssize_t **rows, const Py_ssize_t *depths,
                                         Py_ssize_t n_parents, const int *n_choices, int m,
                                         unsigned long long cap) {
    unsigned long long total = 0;
    for (Py_ssize_t p = 0; p < n_parents; p++) {
        int zero = 0;
        for (Py_ssize_t t = 0; t < depths[p]; t++)
            if (n_choices[rows[p][t]] == 0) zero = 1;
        if (zero) continue;
        unsigned long long count = 1ull << m;
        for (Py_ssize_t t = 0; t < depths[p] && count <= cap; t++)
            count *= (unsigned long long)n_choices[rows[p][t]]; /* (cap <= 2^50, m <= 30) */
        if (count > cap) return cap + 1;
        total += count;
        if (total > cap) return cap + 1;
    }
    return total;
}

#define FAIL(code) \
    do {           \
        result = (code); \
        goto done; \
    } while (0)

static PyObject *list_children(PyObject *self, PyObject *const *args, Py_ssize_t nargs) {
    (void)self;
    if (nargs != 12) {
        PyErr_SetString(PyExc_TypeError, "list_children takes 12 arguments");
        return NULL;
    }
    if (!labelled_assignment) {
        PyErr_SetString(PyExc_RuntimeError, "_clisting.setup() was not called");
        return NULL;
    }
    PyObject *result = NULL;
    PyObject *priors_f = NULL, *rows_f = NULL, *tm_f = NULL;
    Py_ssize_t n_parents = 0, n = 0;
    double *priors = NULL;
    Py_ssize_t **rows = NULL, *depths = NULL, *row_store = NULL;
    double *c_occ = NULL, *c_del = NULL, *c_new = NULL, *c_fal = NULL;
    Choice *choice_store = NULL;
    Py_ssize_t *order = NULL;
    Lister L;
    memset(&L, 0, sizeof(L));

    Py_ssize_t k = PyLong_AsSsize_t(args[7]);
    if (k == -1 && PyErr_Occurred()) return NULL;
    double max_gap = PyFloat_AsDouble(args[8]);
    if (max_gap == -1.0 && PyErr_Occurred()) return NULL;
    long long limit = PyLong_AsLongLong(args[9]);
    if (limit == -1 && PyErr_Occurred()) return NULL;
    int shortcut = PyObject_IsTrue(args[10]);
    if (shortcut < 0) return NULL;
    long long budget = PyLong_AsLongLong(args[11]);
    if (budget == -1 && PyErr_Occurred()) return NULL;
    Py_ssize_t m = PyObject_Length(args[5]);
    if (m < 0) return NULL;

    priors_f = PySequence_Fast(args[0], "priors");
    if (!priors_f) goto done;
    rows_f = PySequence_Fast(args[1], "rows");
    if (!rows_f) goto done;
    tm_f = PySequence_Fast(args[2], "tm");
    if (!tm_f) goto done;
    n_parents = PySequence_Fast_GET_SIZE(rows_f);
    n = PySequence_Fast_GET_SIZE(tm_f);
    if (PySequence_Fast_GET_SIZE(priors_f) != n_parents) {
        PyErr_SetString(PyExc_ValueError, "priors and rows differ in length");
        goto done;
    }
    /* each parent's rows */
    rows = (Py_ssize_t **)PyMem_Malloc((size_t)(n_parents + 1) * sizeof(Py_ssize_t *));
    depths = (Py_ssize_t *)PyMem_Malloc((size_t)(n_parents + 1) * sizeof(Py_ssize_t));
    if (!rows || !depths) {
        PyErr_NoMemory();
        goto done;
    }
    Py_ssize_t total_rows = 0, max_depth = 0;
    int all_short = 1;
    PyObject **row_items = PySequence_Fast_ITEMS(rows_f);
    for (Py_ssize_t p = 0; p < n_parents; p++) {
        Py_ssize_t d = PyObject_Length(row_items[p]);
        if (d < 0) goto done;
        depths[p] = d;
        total_rows += d;
        if (d > max_depth) max_depth = d;
        if (d > 1) all_short = 0;
    }
    if (shortcut && m <= 1 && all_short) FAIL(Py_NewRef(Py_NotImplemented));
    if (m > max_listed) FAIL(Py_NewRef(Py_None));
    /* (k < 1: the Python listing raises; a limit this large: its count is exact) */
    if (k < 1 || m > MAX_M || limit > (1ll << 50)) FAIL(Py_NewRef(Py_NotImplemented));
    row_store = (Py_ssize_t *)PyMem_Malloc((size_t)(total_rows + 1) * sizeof(Py_ssize_t));
    if (!row_store) {
        PyErr_NoMemory();
        goto done;
    }
    Py_ssize_t at = 0;
    for (Py_ssize_t p = 0; p < n_parents; p++) {
        PyObject *r = PySequence_Fast(row_items[p], "rows");
        if (!r) goto done;
        rows[p] = row_store + at;
        PyObject **ri = PySequence_Fast_ITEMS(r);
        for (Py_ssize_t t = 0; t < depths[p]; t++) {
            Py_ssize_t v = PyNumber_AsSsize_t(ri[t], PyExc_OverflowError);
            if (v == -1 && PyErr_Occurred()) {
                Py_DECREF(r);
                goto done;
            }
            if (v < 0 || v >= n) {
                Py_DECREF(r);
                PyErr_SetString(PyExc_IndexError, "rows: node index out of range");
                goto done;
            }
            row_store[at++] = v;
        }
        Py_DECREF(r);
    }
    /* priors (a NaN: Python's sort decides the order) */
    priors = (double *)PyMem_Malloc((size_t)(n_parents + 1) * sizeof(double));
    c_occ = (double *)PyMem_Malloc((size_t)(n + 1) * sizeof(double));
    c_del = (double *)PyMem_Malloc((size_t)(n + 1) * sizeof(double));
    c_new = (double *)PyMem_Malloc((size_t)(m + 1) * sizeof(double));
    c_fal = (double *)PyMem_Malloc((size_t)(m + 1) * sizeof(double));
    if (!priors || !c_occ || !c_del || !c_new || !c_fal) {
        PyErr_NoMemory();
        goto done;
    }
    if (read_doubles(priors_f, priors, n_parents, "priors") < 0) goto done;
    for (Py_ssize_t p = 0; p < n_parents; p++)
        if (isnan(priors[p])) FAIL(Py_NewRef(Py_NotImplemented));
    if (read_doubles(args[3], c_occ, n, "c_occ") < 0) goto done;
    if (read_doubles(args[4], c_del, n, "c_del") < 0) goto done;
    if (read_doubles(args[5], c_new, m, "c_new") < 0) goto done;
    if (read_doubles(args[6], c_fal, m, "c_fal") < 0) goto done;

    /* each node's finite labels, cheapest first, its cheapest cost and its gate */
    L.choices = (Choice **)PyMem_Malloc((size_t)(n + 1) * sizeof(Choice *));
    L.n_choices = (int *)PyMem_Malloc((size_t)(n + 1) * sizeof(int));
    L.cheapest = (double *)PyMem_Malloc((size_t)(n + 1) * sizeof(double));
    L.gates = (unsigned *)PyMem_Malloc((size_t)(n + 1) * sizeof(unsigned));
    choice_store = (Choice *)PyMem_Malloc((size_t)(n * (m + 2) + 1) * sizeof(Choice));
    if (!L.choices || !L.n_choices || !L.cheapest || !L.gates || !choice_store) {
        PyErr_NoMemory();
        goto done;
    }
    PyObject **tm_items = PySequence_Fast_ITEMS(tm_f);
    for (Py_ssize_t i = 0; i < n; i++) {
        Choice *ch = choice_store + i * (m + 2);
        int nc = 0;
        unsigned gate = 0;
        PyObject *row = PySequence_Fast(tm_items[i], "tm");
        if (!row) goto done;
        if (PySequence_Fast_GET_SIZE(row) != m) {
            Py_DECREF(row);
            PyErr_SetString(PyExc_ValueError, "tm: a row's length is not the measurements'");
            goto done;
        }
        PyObject **ri = PySequence_Fast_ITEMS(row);
        for (Py_ssize_t j = 0; j < m; j++) {
            double c = PyFloat_AsDouble(ri[j]);
            if (c == -1.0 && PyErr_Occurred()) {
                Py_DECREF(row);
                goto done;
            }
            if (c < INFINITY) {
                ch[nc].cost = c;
                ch[nc].label = DETECTED;
                ch[nc].meas = (int)j;
                ch[nc].bit = 1u << j;
                nc++;
                gate |= 1u << j;
            }
        }
        Py_DECREF(row);
        if (c_occ[i] < INFINITY) {
            ch[nc].cost = c_occ[i];
            ch[nc].label = OCCLUDED;
            ch[nc].meas = -1;
            ch[nc].bit = 0;
            nc++;
        }
        if (c_del[i] < INFINITY) {
            ch[nc].cost = c_del[i];
            ch[nc].label = DELETED;
            ch[nc].meas = -1;
            ch[nc].bit = 0;
            nc++;
        }
        sort_choices(ch, nc);
        L.choices[i] = ch;
        L.n_choices[i] = nc;
        L.cheapest[i] = nc ? ch[0].cost : INFINITY;
        L.gates[i] = gate;
    }
    int budgeted = 0;
    if (children_bound(rows, depths, n_parents, L.n_choices, (int)m,
                       limit < 0 ? 0ull : (unsigned long long)limit) >
            (limit < 0 ? 0ull : (unsigned long long)limit) ||
        limit < 0) {
        if (budget <= 0) FAIL(Py_NewRef(Py_None));
        budgeted = 1;
    }
    /* the measurements' unmatched labels, cheapest first */
    for (Py_ssize_t j = 0; j < m; j++) {
        int nc = 0;
        if (c_new[j] < INFINITY) {
            L.meas_choices[j][nc].cost = c_new[j];
            L.meas_choices[j][nc].label = NEW_LABEL;
            nc++;
        }
        if (c_fal[j] < INFINITY) {
            L.meas_choices[j][nc].cost = c_fal[j];
            L.meas_choices[j][nc].label = FALSE_ALARM;
            nc++;
        }
        if (nc == 2 && L.meas_choices[j][1].cost < L.meas_choices[j][0].cost) {
            MeasChoice x = L.meas_choices[j][0];
            L.meas_choices[j][0] = L.meas_choices[j][1];
            L.meas_choices[j][1] = x;
        }
        L.n_meas_choices[j] = nc;
        L.meas_min[j] = nc ? L.meas_choices[j][0].cost : INFINITY;
    }
    /* lower bounds of the measurements in a bit mask: unmatched for sure / perhaps matched */
    unsigned full = (1u << m) - 1u;
    L.unmatched_lb = (double *)PyMem_Malloc(((size_t)full + 1) * sizeof(double));
    L.maybe_lb = (double *)PyMem_Malloc(((size_t)full + 1) * sizeof(double));
    L.kept = (double *)PyMem_Malloc((size_t)k * sizeof(double));
    L.suffix = (double *)PyMem_Malloc((size_t)(max_depth + 1) * sizeof(double));
    L.reach = (unsigned *)PyMem_Malloc((size_t)(max_depth + 1) * sizeof(unsigned));
    L.labels = (int *)PyMem_Malloc((size_t)(max_depth + 1) * sizeof(int));
    L.meas = (int *)PyMem_Malloc((size_t)(max_depth + 1) * sizeof(int));
    order = (Py_ssize_t *)PyMem_Malloc((size_t)(n_parents + 1) * sizeof(Py_ssize_t));
    if (!L.unmatched_lb || !L.maybe_lb || !L.kept || !L.suffix || !L.reach || !L.labels ||
        !L.meas || !order) {
        PyErr_NoMemory();
        goto done;
    }
    L.unmatched_lb[0] = 0.0;
    L.maybe_lb[0] = 0.0;
    for (unsigned mask = 1; mask <= full; mask++) {
        int low = 0;
        while (!(mask >> low & 1u)) low++;
        unsigned rest = mask & (mask - 1u);
        double mm = L.meas_min[low];
        L.unmatched_lb[mask] = L.unmatched_lb[rest] + mm;
        L.maybe_lb[mask] = L.maybe_lb[rest] + (mm < 0.0 ? mm : 0.0);
    }
    L.k = k;
    L.max_gap = max_gap;
    L.m = (int)m;
    L.full = full;
    L.best = INFINITY;
    L.limit = INFINITY + max_gap;
    L.kth = NAN;
    L.budgeted = budgeted;
    L.left = budget;
    for (Py_ssize_t j = 0; j < m; j++) L.free_labels[j] = MATCHED;

    /* the parents, the likeliest first (a stable sort by prior; no NaN) */
    for (Py_ssize_t p = 0; p < n_parents; p++) {
        Py_ssize_t q = p;
        while (q > 0 && priors[p] < priors[order[q - 1]]) {
            order[q] = order[q - 1];
            q--;
        }
        order[q] = p;
    }
    for (Py_ssize_t q = 0; q < n_parents; q++) {
        Py_ssize_t pi = order[q];
        if (!isfinite(priors[pi])) continue;
        list_parent(&L, pi, priors[pi], rows[pi], depths[pi]);
        if (L.no_memory) {
            PyErr_NoMemory();
            goto done;
        }
        if (L.out_of_steps) FAIL(Py_NewRef(Py_None));
    }
    if (sort_found(L.found, L.n_found) < 0) FAIL(Py_NewRef(Py_NotImplemented));
    Py_ssize_t n_out = 0;
    Py_ssize_t first = L.n_found < k ? L.n_found : k;
    double keep = L.best + max_gap;
    for (Py_ssize_t i = 0; i < first; i++)
        if (L.found[i].total <= keep) n_out++;
    PyObject *out = PyList_New(n_out);
    if (!out) goto done;
    int *labels = PyMem_Malloc((size_t)(m + 1) * sizeof(int));
    if (!labels) {
        Py_DECREF(out);
        PyErr_NoMemory();
        goto done;
    }
    Py_ssize_t o = 0;
    for (Py_ssize_t i = 0; i < first; i++) {
        const Found *f = &L.found[i];
        if (!(f->total <= keep)) continue;
        const int *a = L.arena + f->at;
        for (Py_ssize_t j = 0; j < m; j++)
            labels[j] = (f->used >> j & 1u) ? MATCHED : a[2 * f->depth + j];
        PyObject *tl = int_list(a, f->depth);
        PyObject *tmeas = int_tuple(a + f->depth, f->depth);
        PyObject *ml = int_list(labels, m);
        PyObject *total = PyFloat_FromDouble(f->total);
        PyObject *pi = PyLong_FromSsize_t(f->parent);
        PyObject *dec = NULL, *item = NULL;
        if (tl && tmeas && ml && total && pi) {
            PyObject *la_args[4] = {tl, tmeas, ml, total};
            dec = PyObject_Vectorcall(labelled_assignment, la_args, 4, NULL);
        }
        if (dec) item = PyTuple_Pack(3, pi, dec, total);
        Py_XDECREF(tl);
        Py_XDECREF(tmeas);
        Py_XDECREF(ml);
        Py_XDECREF(total);
        Py_XDECREF(pi);
        Py_XDECREF(dec);
        if (!item) {
            PyMem_Free(labels);
            Py_DECREF(out);
            goto done;
        }
        PyList_SET_ITEM(out, o++, item);
    }
    PyMem_Free(labels);
    result = out;

done:
    Py_XDECREF(priors_f);
    Py_XDECREF(rows_f);
    Py_XDECREF(tm_f);
    PyMem_Free(priors);
    PyMem_Free(rows);
    PyMem_Free(depths);
    PyMem_Free(row_store);
    PyMem_Free(c_occ);
    PyMem_Free(c_del);
    PyMem_Free(c_new);
    PyMem_Free(c_fal);
    PyMem_Free(choice_store);
    PyMem_Free(order);
    PyMem_Free(L.choices);
    PyMem_Free(L.n_choices);
    PyMem_Free(L.cheapest);
    PyMem_Free(L.gates);
    PyMem_Free(L.unmatched_lb);
    PyMem_Free(L.maybe_lb);
    PyMem_Free(L.kept);
    PyMem_Free(L.suffix);
    PyMem_Free(L.reach);
    PyMem_Free(L.labels);
    PyMem_Free(L.meas);
    PyMem_Free(L.found);
    PyMem_Free(L.arena);
    return result;
}

static PyObject *setup(PyObject *self, PyObject *args) {
    (void)self;
    PyObject *cls;
    int max_m, detected, occluded, deleted, matched, new_label, false_alarm;
    if (!PyArg_ParseTuple(args, "Oi(iii)(iii)", &cls, &max_m, &detected, &occluded,
                          &deleted, &matched, &new_label, &false_alarm))
        return NULL;
    if (detected != DETECTED || occluded != OCCLUDED || deleted != DELETED ||
        matched != MATCHED || new_label != NEW_LABEL || false_alarm != FALSE_ALARM) {
        PyErr_SetString(PyExc_ValueError, "the labels are not the ones compiled in");
        return NULL;
    }
    if (max_m < 0 || max_m > MAX_M) {
        PyErr_Format(PyExc_ValueError, "at most %d listed measurements", MAX_M);
        return NULL;
    }
    Py_INCREF(cls);
    Py_XSETREF(labelled_assignment, cls);
    max_listed = max_m;
    Py_RETURN_NONE;
}

static PyMethodDef methods[] = {
    {"list_children", (PyCFunction)(void (*)(void))list_children, METH_FASTCALL,
     "list_children(priors, rows, tm, c_occ, c_del, c_new, c_fal, k, max_gap, limit, "
     "shortcut, budget): listing.list_children's children, None, or NotImplemented for a "
     "call the Python listing takes (the shortcut, a NaN prior, k < 1)."},
    {"setup", setup, METH_VARARGS,
     "setup(LabelledAssignment, max_listed_measurements, (DETECTED, OCCLUDED, DELETED), "
     "(MATCHED, NEW, FALSE_ALARM))"},
    {NULL, NULL, 0, NULL},
};

static struct PyModuleDef module = {
    PyModuleDef_HEAD_INIT, "_clisting",
    "The leg MHT's listing of a cluster's k best children, compiled (see listing.py).", -1,
    methods, NULL, NULL, NULL, NULL,
};

PyMODINIT_FUNC PyInit__clisting(void) {
    PyObject *mod = PyModule_Create(&module);
    if (!mod) return NULL;
    if (PyModule_AddStringConstant(mod, "SOURCE_HASH", LP_SOURCE_HASH) < 0) {
        Py_DECREF(mod);
        return NULL;
    }
    return mod;
}
