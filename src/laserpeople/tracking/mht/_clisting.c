/* The leg MHT's depth-first listing of a cluster's k best children, compiled (and, at the
 * end of this file, the general path's children: their plan, nodes, hypotheses and pruning,
 * `plan_plain`, `make_plain`, `assemble_plain`, `prune`; a scan's detection costs,
 * `detection_costs`; the scan's clusters, `components`, the occupancy grid's static time
 * of a few positions, `static_few`, a frame's distances from its laser, `grid_frame`,
 * its cells hit by a frame, `grid_hits`, `grid_mark`,
 * the free-space casting of a laser standing still, `still_cast_usual`, `still_cast_apply`,
 * the beam
 * histogram's foreground of a frame, `histogram_foreground`, and a scan's beams without
 * a valid return by kind, `beam_kinds`; and the clustering of 2D points of the particle
 * filters: single-linkage labels, `single_linkage_labels`, per-cluster statistics,
 * `cluster_stats`, flat-kernel mean shift over the dense kernel, `mean_shift_dense`, and the
 * links between the clusters of two scans, `cluster_links`, each point's nearest of a
 * few others, `nearest_points`, and the close pairs of a few points, `close_pairs`).
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

#include "../../_cbuffers.h"

#ifndef LP_SOURCE_HASH
#define LP_SOURCE_HASH ""
#endif

/* labels (probability.py) */
enum { DETECTED = 0, OCCLUDED = 1, DELETED = 2 };
enum { MATCHED = 0, NEW_LABEL = 1, FALSE_ALARM = 2 };
#define MAX_M 30 /* measurement bit masks fit an unsigned int */

/* set by setup() */
static PyObject *labelled_assignment = NULL; /* matrix.LabelledAssignment */
static PyObject *node_id_name = NULL;        /* "node_id", interned */
static int max_listed = 10;                  /* listing.MAX_LISTED_MEASUREMENTS */
static long long listing_limit = 1000000;    /* listing.LISTING_LIMIT */
static long long listing_budget = 2000;      /* listing.LISTING_BUDGET */

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

/* --- helpers --------------------------------------------------------------------- */

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

/* a new list (as_tuple 0) or tuple (1) of the n ints v */
static PyObject *int_seq(const int *v, Py_ssize_t n, int as_tuple) {
    PyObject *out = as_tuple ? PyTuple_New(n) : PyList_New(n);
    if (!out) return NULL;
    for (Py_ssize_t i = 0; i < n; i++) {
        PyObject *x = PyLong_FromLong(v[i]);
        if (!x) {
            Py_DECREF(out);
            return NULL;
        }
        if (as_tuple)
            PyTuple_SET_ITEM(out, i, x);
        else
            PyList_SET_ITEM(out, i, x);
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

/* --- one cluster's listing ------------------------------------------------------------ */

typedef struct {
    Py_ssize_t n_parents;
    double *priors;     /* per parent (no NaN) */
    Py_ssize_t **rows;  /* per parent, its nodes */
    Py_ssize_t *depths; /* per parent, its number of nodes */
    Py_ssize_t max_depth;
    Py_ssize_t n, m;    /* nodes, measurements (m <= max_listed) */
    double *tm;         /* (n, m) detection costs, row-major */
    double *c_occ, *c_del, *c_new, *c_fal;
    Py_ssize_t k;       /* >= 1 */
    double max_gap;
    long long limit;    /* <= 2^50 */
    long long budget;
} Problem;

static void free_lister(Lister *L) {
    PyMem_Free(L->choices);
    PyMem_Free(L->n_choices);
    PyMem_Free(L->cheapest);
    PyMem_Free(L->gates);
    PyMem_Free(L->unmatched_lb);
    PyMem_Free(L->maybe_lb);
    PyMem_Free(L->kept);
    PyMem_Free(L->suffix);
    PyMem_Free(L->reach);
    PyMem_Free(L->labels);
    PyMem_Free(L->meas);
    PyMem_Free(L->found);
    PyMem_Free(L->arena);
}

/* The children of listing.list_children_python's branch and bound: a new list, None (over
 * the limit without a budget, or out of steps), NotImplemented (NaN totals: Python's sort
 * decides their order), or NULL with an exception set. */
static PyObject *solve(const Problem *P) {
    PyObject *result = NULL;
    Py_ssize_t n = P->n, m = P->m, k = P->k;
    Choice *choice_store = NULL;
    Py_ssize_t *order = NULL;
    int *labels = NULL;
    Lister L;
    memset(&L, 0, sizeof(L));

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
    for (Py_ssize_t i = 0; i < n; i++) {
        Choice *ch = choice_store + i * (m + 2);
        const double *row = P->tm + i * m;
        int nc = 0;
        unsigned gate = 0;
        for (Py_ssize_t j = 0; j < m; j++) {
            if (row[j] < INFINITY) {
                ch[nc].cost = row[j];
                ch[nc].label = DETECTED;
                ch[nc].meas = (int)j;
                ch[nc].bit = 1u << j;
                nc++;
                gate |= 1u << j;
            }
        }
        if (P->c_occ[i] < INFINITY) {
            ch[nc].cost = P->c_occ[i];
            ch[nc].label = OCCLUDED;
            ch[nc].meas = -1;
            ch[nc].bit = 0;
            nc++;
        }
        if (P->c_del[i] < INFINITY) {
            ch[nc].cost = P->c_del[i];
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
    unsigned long long cap = P->limit < 0 ? 0ull : (unsigned long long)P->limit;
    if (P->limit < 0 ||
        children_bound(P->rows, P->depths, P->n_parents, L.n_choices, (int)m, cap) > cap) {
        if (P->budget <= 0) {
            result = Py_NewRef(Py_None);
            goto done;
        }
        budgeted = 1;
    }
    /* the measurements' unmatched labels, cheapest first */
    for (Py_ssize_t j = 0; j < m; j++) {
        int nc = 0;
        if (P->c_new[j] < INFINITY) {
            L.meas_choices[j][nc].cost = P->c_new[j];
            L.meas_choices[j][nc].label = NEW_LABEL;
            nc++;
        }
        if (P->c_fal[j] < INFINITY) {
            L.meas_choices[j][nc].cost = P->c_fal[j];
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
    Py_ssize_t max_depth = P->max_depth;
    L.unmatched_lb = (double *)PyMem_Malloc(((size_t)full + 1) * sizeof(double));
    L.maybe_lb = (double *)PyMem_Malloc(((size_t)full + 1) * sizeof(double));
    L.kept = (double *)PyMem_Malloc((size_t)k * sizeof(double));
    L.suffix = (double *)PyMem_Malloc((size_t)(max_depth + 1) * sizeof(double));
    L.reach = (unsigned *)PyMem_Malloc((size_t)(max_depth + 1) * sizeof(unsigned));
    L.labels = (int *)PyMem_Malloc((size_t)(max_depth + 1) * sizeof(int));
    L.meas = (int *)PyMem_Malloc((size_t)(max_depth + 1) * sizeof(int));
    order = (Py_ssize_t *)PyMem_Malloc((size_t)(P->n_parents + 1) * sizeof(Py_ssize_t));
    labels = (int *)PyMem_Malloc((size_t)(m + 1) * sizeof(int));
    if (!L.unmatched_lb || !L.maybe_lb || !L.kept || !L.suffix || !L.reach || !L.labels ||
        !L.meas || !order || !labels) {
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
    L.max_gap = P->max_gap;
    L.m = (int)m;
    L.full = full;
    L.best = INFINITY;
    L.limit = INFINITY + P->max_gap;
    L.kth = NAN;
    L.budgeted = budgeted;
    L.left = P->budget;
    for (Py_ssize_t j = 0; j < m; j++) L.free_labels[j] = MATCHED;

    /* the parents, the likeliest first (a stable sort by prior; no NaN) */
    const double *priors = P->priors;
    for (Py_ssize_t p = 0; p < P->n_parents; p++) {
        Py_ssize_t q = p;
        while (q > 0 && priors[p] < priors[order[q - 1]]) {
            order[q] = order[q - 1];
            q--;
        }
        order[q] = p;
    }
    for (Py_ssize_t q = 0; q < P->n_parents; q++) {
        Py_ssize_t pi = order[q];
        if (!isfinite(priors[pi])) continue;
        list_parent(&L, pi, priors[pi], P->rows[pi], P->depths[pi]);
        if (L.no_memory) {
            PyErr_NoMemory();
            goto done;
        }
        if (L.out_of_steps) {
            result = Py_NewRef(Py_None);
            goto done;
        }
    }
    if (sort_found(L.found, L.n_found) < 0) {
        result = Py_NewRef(Py_NotImplemented);
        goto done;
    }
    Py_ssize_t n_out = 0;
    Py_ssize_t first = L.n_found < k ? L.n_found : k;
    double keep = L.best + P->max_gap;
    for (Py_ssize_t i = 0; i < first; i++)
        if (L.found[i].total <= keep) n_out++;
    PyObject *out = PyList_New(n_out);
    if (!out) goto done;
    Py_ssize_t o = 0;
    for (Py_ssize_t i = 0; i < first; i++) {
        const Found *f = &L.found[i];
        if (!(f->total <= keep)) continue;
        const int *a = L.arena + f->at;
        for (Py_ssize_t j = 0; j < m; j++)
            labels[j] = (f->used >> j & 1u) ? MATCHED : a[2 * f->depth + j];
        PyObject *tl = int_seq(a, f->depth, 0);
        PyObject *tmeas = int_seq(a + f->depth, f->depth, 1);
        PyObject *ml = int_seq(labels, m, 0);
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
            Py_DECREF(out);
            goto done;
        }
        PyList_SET_ITEM(out, o++, item);
    }
    result = out;

done:
    PyMem_Free(choice_store);
    PyMem_Free(order);
    PyMem_Free(labels);
    free_lister(&L);
    return result;
}

/* A problem's arrays, freed together. */
typedef struct {
    Problem P;
    Py_ssize_t *row_store;
} Owned;

static void free_owned(Owned *o) {
    PyMem_Free(o->P.priors);
    PyMem_Free(o->P.rows);
    PyMem_Free(o->P.depths);
    PyMem_Free(o->P.tm);
    PyMem_Free(o->P.c_occ);
    PyMem_Free(o->P.c_del);
    PyMem_Free(o->P.c_new);
    PyMem_Free(o->P.c_fal);
    PyMem_Free(o->row_store);
}

/* the per-parent and per-node arrays of a problem of n_parents parents, total_rows track
 * entries, n nodes and m measurements */
static int alloc_owned(Owned *o, Py_ssize_t n_parents, Py_ssize_t total_rows, Py_ssize_t n,
                       Py_ssize_t m) {
    Problem *P = &o->P;
    P->n_parents = n_parents;
    P->n = n;
    P->m = m;
    P->priors = (double *)PyMem_Malloc((size_t)(n_parents + 1) * sizeof(double));
    P->rows = (Py_ssize_t **)PyMem_Malloc((size_t)(n_parents + 1) * sizeof(Py_ssize_t *));
    P->depths = (Py_ssize_t *)PyMem_Malloc((size_t)(n_parents + 1) * sizeof(Py_ssize_t));
    P->tm = (double *)PyMem_Malloc((size_t)(n * m + 1) * sizeof(double));
    P->c_occ = (double *)PyMem_Malloc((size_t)(n + 1) * sizeof(double));
    P->c_del = (double *)PyMem_Malloc((size_t)(n + 1) * sizeof(double));
    P->c_new = (double *)PyMem_Malloc((size_t)(m + 1) * sizeof(double));
    P->c_fal = (double *)PyMem_Malloc((size_t)(m + 1) * sizeof(double));
    o->row_store = (Py_ssize_t *)PyMem_Malloc((size_t)(total_rows + 1) * sizeof(Py_ssize_t));
    if (!P->priors || !P->rows || !P->depths || !P->tm || !P->c_occ || !P->c_del ||
        !P->c_new || !P->c_fal || !o->row_store) {
        PyErr_NoMemory();
        return -1;
    }
    return 0;
}

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

/* list_children(priors, rows, tm, c_occ, c_del, c_new, c_fal, k, max_gap, limit, shortcut,
 * budget) */
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

    PyObject *result = NULL;
    PyObject *priors_f = NULL, *rows_f = NULL, *tm_f = NULL;
    Owned o;
    memset(&o, 0, sizeof(o));
    Problem *P = &o.P;
    priors_f = PySequence_Fast(args[0], "priors");
    if (!priors_f) goto done;
    rows_f = PySequence_Fast(args[1], "rows");
    if (!rows_f) goto done;
    tm_f = PySequence_Fast(args[2], "tm");
    if (!tm_f) goto done;
    Py_ssize_t n_parents = PySequence_Fast_GET_SIZE(rows_f);
    Py_ssize_t n = PySequence_Fast_GET_SIZE(tm_f);
    if (PySequence_Fast_GET_SIZE(priors_f) != n_parents) {
        PyErr_SetString(PyExc_ValueError, "priors and rows differ in length");
        goto done;
    }
    Py_ssize_t total_rows = 0, max_depth = 0;
    int all_short = 1;
    PyObject **row_items = PySequence_Fast_ITEMS(rows_f);
    for (Py_ssize_t p = 0; p < n_parents; p++) {
        Py_ssize_t d = PyObject_Length(row_items[p]);
        if (d < 0) goto done;
        total_rows += d;
        if (d > max_depth) max_depth = d;
        if (d > 1) all_short = 0;
    }
    if (shortcut && m <= 1 && all_short) {
        result = Py_NewRef(Py_NotImplemented);
        goto done;
    }
    if (m > max_listed) {
        result = Py_NewRef(Py_None);
        goto done;
    }
    /* (k < 1: the Python listing raises; a limit this large: its count is exact) */
    if (k < 1 || m > MAX_M || limit > (1ll << 50)) {
        result = Py_NewRef(Py_NotImplemented);
        goto done;
    }
    if (alloc_owned(&o, n_parents, total_rows, n, m) < 0) goto done;
    P->max_depth = max_depth;
    P->k = k;
    P->max_gap = max_gap;
    P->limit = limit;
    P->budget = budget;
    Py_ssize_t at = 0;
    for (Py_ssize_t p = 0; p < n_parents; p++) {
        PyObject *r = PySequence_Fast(row_items[p], "rows");
        if (!r) goto done;
        Py_ssize_t d = PySequence_Fast_GET_SIZE(r);
        P->rows[p] = o.row_store + at;
        P->depths[p] = d;
        PyObject **ri = PySequence_Fast_ITEMS(r);
        for (Py_ssize_t t = 0; t < d; t++) {
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
            o.row_store[at++] = v;
        }
        Py_DECREF(r);
    }
    if (read_doubles(priors_f, P->priors, n_parents, "priors") < 0) goto done;
    for (Py_ssize_t p = 0; p < n_parents; p++)
        if (isnan(P->priors[p])) { /* (Python's sort decides the order) */
            result = Py_NewRef(Py_NotImplemented);
            goto done;
        }
    if (read_doubles(args[3], P->c_occ, n, "c_occ") < 0) goto done;
    if (read_doubles(args[4], P->c_del, n, "c_del") < 0) goto done;
    if (read_doubles(args[5], P->c_new, m, "c_new") < 0) goto done;
    if (read_doubles(args[6], P->c_fal, m, "c_fal") < 0) goto done;
    PyObject **tm_items = PySequence_Fast_ITEMS(tm_f);
    for (Py_ssize_t i = 0; i < n; i++)
        if (read_doubles(tm_items[i], P->tm + i * m, m, "tm") < 0) goto done;
    result = solve(P);

done:
    Py_XDECREF(priors_f);
    Py_XDECREF(rows_f);
    Py_XDECREF(tm_f);
    free_owned(&o);
    return result;
}

/* k_best_plain(tracks_of, priors, row_of, cost_live, meas_idx, occ_all, del_all, new_all,
 * fal_all, k, max_gap, shortcut, max_cluster_size): MHT._k_best of the plain MHT on this
 * scan's tables (see core.py), as (children, cluster size); NotImplemented for a cluster
 * MHT._k_best's Python takes (a node not scored this scan, over max_cluster_size, the
 * shortcut, listed by Murty's method). */
static PyObject *k_best_plain(PyObject *self, PyObject *const *args, Py_ssize_t nargs) {
    (void)self;
    if (nargs != 13) {
        PyErr_SetString(PyExc_TypeError, "k_best_plain takes 13 arguments");
        return NULL;
    }
    if (!labelled_assignment || !node_id_name) {
        PyErr_SetString(PyExc_RuntimeError, "_clisting.setup() was not called");
        return NULL;
    }
    PyObject *tracks_of = args[0], *priors_l = args[1], *row_of = args[2];
    PyObject *meas_l = args[4], *occ_all = args[5], *del_all = args[6];
    PyObject *new_all = args[7], *fal_all = args[8];
    if (!PyList_Check(tracks_of) || !PyList_Check(priors_l) || !PyDict_Check(row_of) ||
        !PyList_Check(meas_l) || !PyList_Check(occ_all) || !PyList_Check(del_all) ||
        !PyList_Check(new_all) || !PyList_Check(fal_all)) {
        PyErr_SetString(PyExc_TypeError, "k_best_plain: lists and a dict expected");
        return NULL;
    }
    Py_ssize_t k = PyLong_AsSsize_t(args[9]);
    if (k == -1 && PyErr_Occurred()) return NULL;
    double max_gap = PyFloat_AsDouble(args[10]);
    if (max_gap == -1.0 && PyErr_Occurred()) return NULL;
    int shortcut = PyObject_IsTrue(args[11]);
    if (shortcut < 0) return NULL;
    Py_ssize_t max_size = PyLong_AsSsize_t(args[12]);
    if (max_size == -1 && PyErr_Occurred()) return NULL;

    PyObject *result = NULL, *uniq = NULL, *live_rows = NULL;
    Py_buffer table;
    int have_table = 0;
    Owned o;
    memset(&o, 0, sizeof(o));
    Problem *P = &o.P;
    Py_ssize_t n_parents = PyList_GET_SIZE(tracks_of), m = PyList_GET_SIZE(meas_l);
    if (PyList_GET_SIZE(priors_l) != n_parents) {
        PyErr_SetString(PyExc_ValueError, "priors and tracks_of differ in length");
        return NULL;
    }
    Py_ssize_t total_rows = 0, max_depth = 0;
    int all_short = 1;
    for (Py_ssize_t p = 0; p < n_parents; p++) {
        PyObject *tracks = PyList_GET_ITEM(tracks_of, p);
        if (!PyTuple_Check(tracks)) return Py_NewRef(Py_NotImplemented); /* (Python's) */
        Py_ssize_t d = PyTuple_GET_SIZE(tracks);
        total_rows += d;
        if (d > max_depth) max_depth = d;
        if (d > 1) all_short = 0;
    }
    /* (the Python path: the shortcut, Murty's method, k < 1) */
    if ((shortcut && m <= 1 && all_short) || m > max_listed || k < 1)
        return Py_NewRef(Py_NotImplemented);
    uniq = PyDict_New();
    live_rows = PyList_New(0);
    if (!uniq || !live_rows) goto done;
    if (alloc_owned(&o, n_parents, total_rows, total_rows, m) < 0) goto done;
    /* the nodes once each, in order of first appearance, and each parent's rows of them */
    Py_ssize_t at = 0;
    for (Py_ssize_t p = 0; p < n_parents; p++) {
        PyObject *tracks = PyList_GET_ITEM(tracks_of, p);
        Py_ssize_t d = PyTuple_GET_SIZE(tracks);
        P->rows[p] = o.row_store + at;
        P->depths[p] = d;
        for (Py_ssize_t t = 0; t < d; t++) {
            PyObject *node_id = PyObject_GetAttr(PyTuple_GET_ITEM(tracks, t), node_id_name);
            if (!node_id) goto done;
            PyObject *index = PyDict_GetItemWithError(uniq, node_id); /* borrowed */
            Py_ssize_t i;
            if (index) {
                i = PyLong_AsSsize_t(index);
            } else if (PyErr_Occurred()) {
                Py_DECREF(node_id);
                goto done;
            } else {
                PyObject *row = PyDict_GetItemWithError(row_of, node_id); /* borrowed */
                if (!row) {
                    Py_DECREF(node_id);
                    if (PyErr_Occurred()) goto done;
                    result = Py_NewRef(Py_NotImplemented); /* not scored this scan */
                    goto done;
                }
                i = PyList_GET_SIZE(live_rows);
                PyObject *pi = PyLong_FromSsize_t(i);
                int bad = !pi || PyDict_SetItem(uniq, node_id, pi) < 0 ||
                          PyList_Append(live_rows, row) < 0;
                Py_XDECREF(pi);
                if (bad) {
                    Py_DECREF(node_id);
                    goto done;
                }
            }
            Py_DECREF(node_id);
            o.row_store[at++] = i;
        }
    }
    Py_ssize_t n = PyList_GET_SIZE(live_rows);
    Py_ssize_t size = n + m;
    if (size > max_size) { /* (degraded: the Python path) */
        result = Py_NewRef(Py_NotImplemented);
        goto done;
    }
    P->n = n;
    P->max_depth = max_depth;
    P->k = k;
    P->max_gap = max_gap;
    P->limit = listing_limit;
    P->budget = listing_budget;
    if (read_doubles(priors_l, P->priors, n_parents, "priors") < 0) goto done;
    for (Py_ssize_t p = 0; p < n_parents; p++)
        if (isnan(P->priors[p])) {
            result = Py_NewRef(Py_NotImplemented);
            goto done;
        }
    /* the costs: the scan's detection costs table (float64, C order) at the nodes' rows and
     * the cluster's measurements, and the per-scan label costs */
    if (PyObject_GetBuffer(args[3], &table, PyBUF_C_CONTIGUOUS | PyBUF_FORMAT) < 0) {
        PyErr_Clear(); /* (not a C-ordered buffer: the Python path) */
        result = Py_NewRef(Py_NotImplemented);
        goto done;
    }
    have_table = 1;
    if (table.ndim != 2 || table.itemsize != sizeof(double) || !table.format ||
        strcmp(table.format, "d") != 0) {
        result = Py_NewRef(Py_NotImplemented);
        goto done;
    }
    Py_ssize_t n_live = table.shape[0], n_meas = table.shape[1];
    const double *cost = (const double *)table.buf;
    Py_ssize_t *js = (Py_ssize_t *)PyMem_Malloc((size_t)(m + 1) * sizeof(Py_ssize_t));
    if (!js) {
        PyErr_NoMemory();
        goto done;
    }
    for (Py_ssize_t j = 0; j < m; j++) {
        js[j] = PyLong_AsSsize_t(PyList_GET_ITEM(meas_l, j));
        if ((js[j] == -1 && PyErr_Occurred()) || js[j] < 0 || js[j] >= n_meas ||
            js[j] >= PyList_GET_SIZE(new_all) || js[j] >= PyList_GET_SIZE(fal_all)) {
            PyMem_Free(js);
            if (!PyErr_Occurred()) PyErr_SetString(PyExc_IndexError, "measurement index");
            goto done;
        }
        P->c_new[j] = PyFloat_AsDouble(PyList_GET_ITEM(new_all, js[j]));
        P->c_fal[j] = PyFloat_AsDouble(PyList_GET_ITEM(fal_all, js[j]));
    }
    for (Py_ssize_t i = 0; i < n; i++) {
        Py_ssize_t r = PyLong_AsSsize_t(PyList_GET_ITEM(live_rows, i));
        if ((r == -1 && PyErr_Occurred()) || r < 0 || r >= n_live ||
            r >= PyList_GET_SIZE(occ_all) || r >= PyList_GET_SIZE(del_all)) {
            PyMem_Free(js);
            if (!PyErr_Occurred()) PyErr_SetString(PyExc_IndexError, "node row");
            goto done;
        }
        for (Py_ssize_t j = 0; j < m; j++) P->tm[i * m + j] = cost[r * n_meas + js[j]];
        P->c_occ[i] = PyFloat_AsDouble(PyList_GET_ITEM(occ_all, r));
        P->c_del[i] = PyFloat_AsDouble(PyList_GET_ITEM(del_all, r));
    }
    PyMem_Free(js);
    if (PyErr_Occurred()) goto done;
    PyObject *children = solve(P);
    if (!children) goto done;
    if (children == Py_None || children == Py_NotImplemented) { /* (Murty's method) */
        Py_DECREF(children);
        result = Py_NewRef(Py_NotImplemented);
        goto done;
    }
    result = Py_BuildValue("(Nn)", children, size);

done:
    if (have_table) PyBuffer_Release(&table);
    Py_XDECREF(uniq);
    Py_XDECREF(live_rows);
    free_owned(&o);
    return result;
}

static PyObject *setup(PyObject *self, PyObject *args) {
    (void)self;
    PyObject *cls;
    int max_m, detected, occluded, deleted, matched, new_label, false_alarm;
    long long limit, budget;
    if (!PyArg_ParseTuple(args, "Oi(iii)(iii)LL", &cls, &max_m, &detected, &occluded,
                          &deleted, &matched, &new_label, &false_alarm, &limit, &budget))
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
    if (limit < 0 || limit > (1ll << 50)) {
        PyErr_SetString(PyExc_ValueError, "the listing limit is out of 0..2^50");
        return NULL;
    }
    if (!node_id_name) {
        node_id_name = PyUnicode_InternFromString("node_id");
        if (!node_id_name) return NULL;
    }
    Py_INCREF(cls);
    Py_XSETREF(labelled_assignment, cls);
    max_listed = max_m;
    listing_limit = limit;
    listing_budget = budget;
    Py_RETURN_NONE;
}

/* ------------------------------------------------------------------ components
 *
 * core.components_python compiled: the connected components of a scan's families (ints,
 * the keys of fam_meas, in its order) and measurements 0..n_meas-1 by union-find. Which
 * element is a root does not change the result: the components are listed by their first
 * family in fam_meas order, then those of measurements alone by their first measurement;
 * each one's families as a frozenset made from a set filled in fam_meas order (the same
 * table, so the same iteration order, as the Python one's) and its measurements as a list,
 * increasing. Input the Python function would refuse (a link of a family not in fam_meas, a
 * measurement out of range, not an int) returns NotImplemented: the Python one takes it. */

static Py_ssize_t uf_root(Py_ssize_t *up, Py_ssize_t x) {
    Py_ssize_t r = x;
    while (up[r] != r) r = up[r];
    while (up[x] != r) { /* path compression */
        Py_ssize_t next = up[x];
        up[x] = r;
        x = next;
    }
    return r;
}

static void uf_join(Py_ssize_t *up, Py_ssize_t a, Py_ssize_t b) {
    Py_ssize_t ra = uf_root(up, a), rb = uf_root(up, b);
    if (ra != rb) up[rb] = ra;
}

/* The index (in fam_meas order) of family `key`, -1 when it is not one, -2 on an error. */
static Py_ssize_t family_index(PyObject *index, PyObject *key) {
    PyObject *v = PyDict_GetItemWithError(index, key);
    if (!v) return PyErr_Occurred() ? -2 : -1;
    return PyLong_AsSsize_t(v);
}

static PyObject *components(PyObject *self, PyObject *const *args, Py_ssize_t nargs) {
    (void)self;
    if (nargs != 3) {
        PyErr_SetString(PyExc_TypeError, "components(fam_meas, links, n_meas)");
        return NULL;
    }
    PyObject *fam_meas = args[0], *links = args[1];
    Py_ssize_t n_meas = PyLong_AsSsize_t(args[2]);
    if (n_meas == -1 && PyErr_Occurred()) return NULL;
    if (!PyDict_CheckExact(fam_meas) || n_meas < 0) Py_RETURN_NOTIMPLEMENTED;
    Py_ssize_t nf = PyDict_GET_SIZE(fam_meas), total = nf + n_meas;
    PyObject *result = NULL, *index = NULL, *it = NULL, *item = NULL;
    PyObject **fams = PyMem_Malloc((size_t)(nf + 1) * sizeof(PyObject *));
    Py_ssize_t *up = PyMem_Malloc((size_t)(total + 1) * sizeof(Py_ssize_t));
    Py_ssize_t *slot = PyMem_Malloc((size_t)(total + 1) * sizeof(Py_ssize_t));
    PyObject **sets = PyMem_Calloc((size_t)(total + 1), sizeof(PyObject *));
    PyObject **lists = PyMem_Calloc((size_t)(total + 1), sizeof(PyObject *));
    Py_ssize_t ncomp = 0, i, pos = 0;
    PyObject *key, *value;
    int refused = 0;
    if (!fams || !up || !slot || !sets || !lists) {
        PyErr_NoMemory();
        goto done;
    }
    index = PyDict_New();
    if (!index) goto done;
    for (i = 0; i < total; i++) up[i] = i, slot[i] = -1;
    for (i = 0; PyDict_Next(fam_meas, &pos, &key, &value); i++) {
        PyObject *at = PyLong_FromSsize_t(i);
        if (!at) goto done;
        int bad = PyDict_SetItem(index, key, at);
        Py_DECREF(at);
        if (bad < 0) goto done;
        fams[i] = key; /* (borrowed: fam_meas holds it through the call) */
    }
    if (PyDict_GET_SIZE(index) != nf) { /* (keys equal but not the same: not ints) */
        refused = 1;
        goto done;
    }
    it = PyObject_GetIter(links);
    if (!it) goto done;
    while ((item = PyIter_Next(it))) {
        if (!PyTuple_CheckExact(item) || PyTuple_GET_SIZE(item) != 2) {
            refused = 1;
            goto done;
        }
        Py_ssize_t a = family_index(index, PyTuple_GET_ITEM(item, 0));
        Py_ssize_t b = family_index(index, PyTuple_GET_ITEM(item, 1));
        if (a == -2 || b == -2) goto done;
        if (a < 0 || b < 0) {
            refused = 1;
            goto done;
        }
        uf_join(up, a, b);
        Py_CLEAR(item);
    }
    if (PyErr_Occurred()) goto done;
    Py_CLEAR(it);
    for (i = 0; i < nf; i++) {
        PyObject *js = PyDict_GetItemWithError(fam_meas, fams[i]);
        if (!js) {
            if (!PyErr_Occurred()) refused = 1;
            goto done;
        }
        it = PyObject_GetIter(js);
        if (!it) goto done;
        while ((item = PyIter_Next(it))) {
            Py_ssize_t j = PyLong_Check(item) ? PyLong_AsSsize_t(item) : -1;
            if (j == -1 && PyErr_Occurred()) PyErr_Clear(); /* (too large: refused) */
            if (j < 0 || j >= n_meas) {
                refused = 1;
                goto done;
            }
            uf_join(up, i, nf + j);
            Py_CLEAR(item);
        }
        if (PyErr_Occurred()) goto done;
        Py_CLEAR(it);
    }
    for (i = 0; i < nf; i++) { /* components by their first family */
        Py_ssize_t r = uf_root(up, i);
        if (slot[r] < 0) {
            slot[r] = ncomp;
            sets[ncomp] = PySet_New(NULL);
            if (!sets[ncomp++]) goto done;
        }
        if (PySet_Add(sets[slot[r]], fams[i]) < 0) goto done;
    }
    for (i = 0; i < n_meas; i++) { /* then those of measurements alone */
        Py_ssize_t r = uf_root(up, nf + i);
        if (slot[r] < 0) slot[r] = ncomp++;
        Py_ssize_t c = slot[r];
        if (!lists[c] && !(lists[c] = PyList_New(0))) goto done;
        PyObject *j = PyLong_FromSsize_t(i);
        if (!j) goto done;
        int bad = PyList_Append(lists[c], j);
        Py_DECREF(j);
        if (bad < 0) goto done;
    }
    result = PyList_New(ncomp);
    if (!result) goto done;
    for (i = 0; i < ncomp; i++) {
        PyObject *fs = PyFrozenSet_New(sets[i]); /* (NULL: the empty one) */
        if (!fs) {
            Py_CLEAR(result);
            goto done;
        }
        if (!lists[i] && !(lists[i] = PyList_New(0))) {
            Py_DECREF(fs);
            Py_CLEAR(result);
            goto done;
        }
        PyObject *pair = PyTuple_Pack(2, fs, lists[i]);
        Py_DECREF(fs);
        if (!pair) {
            Py_CLEAR(result);
            goto done;
        }
        PyList_SET_ITEM(result, i, pair);
    }
done:
    Py_XDECREF(item);
    Py_XDECREF(it);
    Py_XDECREF(index);
    if (sets)
        for (i = 0; i < ncomp; i++) Py_XDECREF(sets[i]);
    if (lists)
        for (i = 0; i < ncomp; i++) Py_XDECREF(lists[i]);
    PyMem_Free(fams);
    PyMem_Free(up);
    PyMem_Free(slot);
    PyMem_Free(sets);
    PyMem_Free(lists);
    if (refused && !result) {
        PyErr_Clear();
        Py_RETURN_NOTIMPLEMENTED;
    }
    return result;
}

/* ------------------------------------------------------------------ static_few
 *
 * OccupancyGrid._static_few_python compiled: the static time [s] of a few positions, the
 * largest over the (2n + 1)^2 cells round each, read from the grid's C-contiguous arrays
 * (evidence, touched, since: float64; first_sight: bool) with the same IEEE operations in
 * the same order (division, floor, subtraction, multiplication; exp is the C library's,
 * which math.exp calls too). NotImplemented wherever the Python one decides otherwise or
 * numpy's exp would (a position not finite or whose cells leave the arrays, a decayed
 * evidence within `near` of the threshold, arrays not as expected): it runs then. */

/* 0 with the C-contiguous 2-D buffer of `obj` of items `format` in `view`, else 1 (no
 * buffer held, no error set: the caller refuses). */
static int grid_buffer(PyObject *obj, Py_buffer *view, const char *format) {
    if (PyObject_GetBuffer(obj, view, PyBUF_C_CONTIGUOUS | PyBUF_FORMAT) < 0) {
        PyErr_Clear(); /* (not an array, or not C-contiguous) */
        return 1;
    }
    if (view->ndim != 2 || !view->format || strcmp(view->format, format) != 0) {
        PyBuffer_Release(view);
        view->obj = NULL;
        return 1;
    }
    return 0;
}

static PyObject *static_few(PyObject *self, PyObject *const *args, Py_ssize_t nargs) {
    (void)self;
    if (nargs != 15) {
        PyErr_SetString(PyExc_TypeError,
                        "static_few(evidence, touched, since, first_sight, o0, o1, xy, "
                        "resolution, n, stamp, decay_time, threshold, hold, extra, near)");
        return NULL;
    }
    Py_buffer bufs[4];
    const char *formats[4] = {"d", "d", "d", "?"};
    int got = 0, refused = 0;
    PyObject *out = NULL;
    long long o0 = PyLong_AsLongLong(args[4]), o1 = PyLong_AsLongLong(args[5]);
    long n = PyLong_AsLong(args[8]);
    double res = PyFloat_AsDouble(args[7]), stamp = PyFloat_AsDouble(args[9]);
    double tau = PyFloat_AsDouble(args[10]), thr = PyFloat_AsDouble(args[11]);
    double hold = PyFloat_AsDouble(args[12]), extra = PyFloat_AsDouble(args[13]);
    double near = PyFloat_AsDouble(args[14]);
    PyObject *xy = args[6];
    if (PyErr_Occurred()) return NULL;
    if (!PyList_CheckExact(xy) || n < 0 || !isfinite(stamp)) Py_RETURN_NOTIMPLEMENTED;
    for (; got < 4; got++) {
        if (grid_buffer(args[got], &bufs[got], formats[got])) {
            refused = 1;
            goto done;
        }
    }
    Py_ssize_t h = bufs[0].shape[0], w = bufs[0].shape[1];
    for (int b = 1; b < 4; b++)
        if (bufs[b].shape[0] != h || bufs[b].shape[1] != w) {
            refused = 1;
            goto done;
        }
    const double *ev = bufs[0].buf, *touched = bufs[1].buf, *since = bufs[2].buf;
    const char *first = bufs[3].buf;
    Py_ssize_t m = PyList_GET_SIZE(xy);
    out = PyList_New(m);
    if (!out) goto done;
    for (Py_ssize_t q = 0; q < m; q++) {
        PyObject *pos = PyList_GET_ITEM(xy, q);
        if (!PyList_CheckExact(pos) || PyList_GET_SIZE(pos) != 2) {
            refused = 1;
            goto done;
        }
        double x = PyFloat_AsDouble(PyList_GET_ITEM(pos, 0));
        double y = PyFloat_AsDouble(PyList_GET_ITEM(pos, 1));
        if (PyErr_Occurred()) goto done;
        if (!isfinite(x) || !isfinite(y)) {
            refused = 1;
            goto done;
        }
        double fi = floor(x / res), fj = floor(y / res);
        if (!(fabs(fi) < 4e18 && fabs(fj) < 4e18)) {
            refused = 1;
            goto done;
        }
        long long i = (long long)fi - o0, j = (long long)fj - o1;
        if (i < n || j < n || i >= h - n || j >= w - n) {
            refused = 1;
            goto done;
        }
        double best = 0.0;
        int first_cell = 1;
        for (long long a = i - n; a <= i + n; a++) {
            for (long long c = j - n; c <= j + n; c++) {
                Py_ssize_t k = (Py_ssize_t)(a * w + c);
                double tk = 0.0, s = since[k];
                if (s == s) { /* (a free cell, since nan, is 0 s static) */
                    double dt = stamp - touched[k];
                    if (dt < 0.0) dt = 0.0;
                    double decayed = ev[k] * exp(-dt / tau);
                    if (fabs(decayed - thr) <= near) { /* numpy's exp decides: Python */
                        refused = 1;
                        goto done;
                    }
                    if (decayed >= thr) tk = stamp - s;
                }
                double t = (first[k] && tk >= hold) ? tk + extra : tk;
                if (first_cell || t > best) best = t; /* (max: the first of the largest) */
                first_cell = 0;
            }
        }
        PyObject *v = PyFloat_FromDouble(best > 0.0 ? best : 0.0);
        if (!v) goto done;
        PyList_SET_ITEM(out, q, v);
    }
done:
    for (int b = 0; b < got; b++) PyBuffer_Release(&bufs[b]);
    if (PyErr_Occurred()) {
        Py_XDECREF(out);
        return NULL;
    }
    if (refused) {
        Py_XDECREF(out);
        Py_RETURN_NOTIMPLEMENTED;
    }
    return out;
}

/* ------------------------------------------------------------------ grid_hits, grid_mark
 *
 * OccupancyGrid._hits_python and _mark_hits_python compiled: a frame's cells with a return
 * (the flat indices of floor(x / resolution), floor(y / resolution) into the grid's arrays,
 * sorted, each once) with the exponents -max(stamp - touched, 0) / decay_time of their
 * decayed evidence; then, given numpy's exp of those exponents (the C library's exp may
 * differ from numpy's in the last bit, and the evidence is kept), the cells' evidence,
 * touched stamps, occupied-since stamps and first-sight flags, with the same IEEE
 * operations as the numpy reference in the same order. NotImplemented for input the
 * Python one takes (a point not finite, a cell outside the arrays, buffers not as
 * expected): nothing is written then. */

/* 0 with the C-contiguous buffer of `obj` (any dimensions) of items `format` (or, with
 * `alt`, that one) in `view`, `len` its number of items, else 1 (no buffer held, no error
 * set: the caller refuses). */
static int flat_buffer(PyObject *obj, Py_buffer *view, const char *format, const char *alt,
                       int writable, Py_ssize_t *len) {
    int flags = PyBUF_C_CONTIGUOUS | PyBUF_FORMAT | (writable ? PyBUF_WRITABLE : 0);
    if (PyObject_GetBuffer(obj, view, flags) < 0) {
        PyErr_Clear();
        return 1;
    }
    if (!view->format ||
        (strcmp(view->format, format) != 0 && !(alt && strcmp(view->format, alt) == 0))) {
        PyBuffer_Release(view);
        view->obj = NULL;
        return 1;
    }
    *len = view->len / view->itemsize;
    return 0;
}

static void release_all(Py_buffer *bufs, int got) {
    for (int b = 0; b < got; b++) PyBuffer_Release(&bufs[b]);
}

/* Sort the non-negative v[0..n) ascending: least significant byte first, one counting
 * pass per byte up to the largest value's (`scratch` holds n items). */
static void sort_cells(long long *v, long long *scratch, Py_ssize_t n) {
    long long top = 0;
    for (Py_ssize_t q = 0; q < n; q++)
        if (v[q] > top) top = v[q];
    for (int shift = 0; shift < 64 && (top >> shift) > 0; shift += 8) {
        Py_ssize_t count[257] = {0};
        for (Py_ssize_t q = 0; q < n; q++) count[((v[q] >> shift) & 0xff) + 1]++;
        for (int d = 0; d < 256; d++) count[d + 1] += count[d];
        for (Py_ssize_t q = 0; q < n; q++) scratch[count[(v[q] >> shift) & 0xff]++] = v[q];
        memcpy(v, scratch, (size_t)n * sizeof(long long));
    }
}

static PyObject *grid_hits(PyObject *self, PyObject *const *args, Py_ssize_t nargs) {
    (void)self;
    if (nargs != 9) {
        PyErr_SetString(PyExc_TypeError,
                        "grid_hits(points, touched, o0, o1, resolution, stamp, decay_time, "
                        "hit_out, exponent_out)");
        return NULL;
    }
    long long o0 = PyLong_AsLongLong(args[2]), o1 = PyLong_AsLongLong(args[3]);
    double res = PyFloat_AsDouble(args[4]), stamp = PyFloat_AsDouble(args[5]);
    double tau = PyFloat_AsDouble(args[6]);
    if (PyErr_Occurred()) return NULL;
    Py_buffer bufs[4];
    int got = 0;
    Py_ssize_t lens[4];
    if (flat_buffer(args[0], &bufs[0], "d", NULL, 0, &lens[0])) goto refuse;
    got = 1;
    if (flat_buffer(args[1], &bufs[1], "d", NULL, 0, &lens[1])) goto refuse;
    got = 2;
    if (flat_buffer(args[7], &bufs[2], "l", "q", 1, &lens[2])) goto refuse;
    got = 3;
    if (flat_buffer(args[8], &bufs[3], "d", NULL, 1, &lens[3])) goto refuse;
    got = 4;
    if (bufs[0].ndim != 2 || bufs[0].shape[1] != 2 || bufs[1].ndim != 2 ||
        bufs[2].itemsize != 8)
        goto refuse;
    Py_ssize_t n = bufs[0].shape[0], h = bufs[1].shape[0], w = bufs[1].shape[1];
    if (lens[2] < n || lens[3] < n) goto refuse;
    const double *pts = bufs[0].buf, *touched = bufs[1].buf;
    long long *hit = bufs[2].buf;
    double *exponent = bufs[3].buf;
    for (Py_ssize_t q = 0; q < n; q++) {
        double x = pts[2 * q], y = pts[2 * q + 1];
        if (!isfinite(x) || !isfinite(y)) goto refuse;
        double fi = floor(x / res), fj = floor(y / res);
        if (!(fabs(fi) < 4e18 && fabs(fj) < 4e18)) goto refuse;
        long long i = (long long)fi - o0, j = (long long)fj - o1;
        if (i < 0 || j < 0 || i >= h || j >= w) goto refuse;
        hit[q] = i * w + j;
    }
    long long *scratch = PyMem_Malloc((size_t)(n > 0 ? n : 1) * sizeof(long long));
    if (!scratch) {
        release_all(bufs, got);
        return PyErr_NoMemory();
    }
    sort_cells(hit, scratch, n);
    PyMem_Free(scratch);
    Py_ssize_t k = 0;
    for (Py_ssize_t q = 0; q < n; q++)
        if (k == 0 || hit[q] != hit[k - 1]) hit[k++] = hit[q];
    for (Py_ssize_t q = 0; q < k; q++) {
        double dt = stamp - touched[hit[q]];
        if (dt < 0.0) dt = 0.0; /* np.maximum(dt, 0.0): nan and -0.0 stay */
        exponent[q] = -dt / tau;
    }
    release_all(bufs, got);
    return PyLong_FromSsize_t(k);
refuse:
    release_all(bufs, got);
    Py_RETURN_NOTIMPLEMENTED;
}

/* OccupancyGrid.learn's look at a frame of one sensor position: the distance of every
 * return from it, hypot(x - ox, y - oy) (the C library's hypot, numpy's; the same
 * subtraction), written to r_out, and returned: the largest of them (0.0 without returns)
 * and whether the beam ids increase strictly along the returns. NotImplemented (r_out
 * not to be read) where a return or the position is not finite: the Python one filters
 * them first. */
static PyObject *grid_frame(PyObject *self, PyObject *const *args, Py_ssize_t nargs) {
    (void)self;
    if (nargs != 5) {
        PyErr_SetString(PyExc_TypeError, "grid_frame(points, ids, ox, oy, r_out)");
        return NULL;
    }
    if (!PyFloat_CheckExact(args[2]) || !PyFloat_CheckExact(args[3])) Py_RETURN_NOTIMPLEMENTED;
    double ox = PyFloat_AS_DOUBLE(args[2]), oy = PyFloat_AS_DOUBLE(args[3]);
    if (!isfinite(ox) || !isfinite(oy)) Py_RETURN_NOTIMPLEMENTED;
    Py_buffer bufs[3];
    Py_ssize_t lens[3];
    int got = 0;
    if (flat_buffer(args[0], &bufs[0], "d", NULL, 0, &lens[0])) goto refuse;
    got = 1;
    if (flat_buffer(args[1], &bufs[1], "l", "q", 0, &lens[1])) goto refuse;
    got = 2;
    if (flat_buffer(args[4], &bufs[2], "d", NULL, 1, &lens[2])) goto refuse;
    got = 3;
    if (bufs[0].ndim != 2 || bufs[0].shape[1] != 2 || bufs[1].itemsize != 8) goto refuse;
    Py_ssize_t n = bufs[0].shape[0];
    if (lens[1] != n || lens[2] != n) goto refuse;
    const double *pts = bufs[0].buf;
    const long long *ids = bufs[1].buf;
    double *r = bufs[2].buf, reach = 0.0;
    int increasing = 1;
    for (Py_ssize_t q = 0; q < n; q++) {
        double x = pts[2 * q], y = pts[2 * q + 1];
        if (!isfinite(x) || !isfinite(y)) goto refuse;
        double d = hypot(x - ox, y - oy);
        r[q] = d;
        if (q == 0 || d > reach) reach = d;
        if (q > 0 && !(ids[q] > ids[q - 1])) increasing = 0;
    }
    release_all(bufs, got);
    return Py_BuildValue("(dO)", reach, increasing ? Py_True : Py_False);
refuse:
    release_all(bufs, got);
    Py_RETURN_NOTIMPLEMENTED;
}

static PyObject *grid_mark(PyObject *self, PyObject *const *args, Py_ssize_t nargs) {
    (void)self;
    if (nargs != 17) {
        PyErr_SetString(PyExc_TypeError,
                        "grid_mark(evidence, touched, since, first_sight, seen_free, hit, "
                        "factor, stamp, occupied, hit_evidence, max_evidence, arrival_window, "
                        "casting, cover, hit_frame, frame, cast_stamp)");
        return NULL;
    }
    double stamp = PyFloat_AsDouble(args[7]), occ = PyFloat_AsDouble(args[8]);
    double add = PyFloat_AsDouble(args[9]), top = PyFloat_AsDouble(args[10]);
    double window = PyFloat_AsDouble(args[11]);
    int casting = PyObject_IsTrue(args[12]);
    long long frame = PyLong_AsLongLong(args[15]);
    double cast_stamp = PyFloat_AsDouble(args[16]);
    if (PyErr_Occurred() || casting < 0) return NULL;
    int live = args[13] != Py_None;
    Py_buffer bufs[9];
    Py_ssize_t lens[9];
    int got = 0;
    const char *formats[9] = {"d", "d", "d", "?", "d", "l", "d", "i", "l"};
    const char *alts[9] = {NULL, NULL, NULL, NULL, NULL, "q", NULL, NULL, "q"};
    const int writable[9] = {1, 1, 1, 1, 0, 0, 0, 0, 0};
    const int which[9] = {0, 1, 2, 3, 4, 5, 6, 13, 14};
    for (int b = 0; b < (live ? 9 : 7); b++) {
        if (flat_buffer(args[which[b]], &bufs[b], formats[b], alts[b], writable[b], &lens[b]))
            goto refuse;
        got = b + 1;
    }
    Py_ssize_t size = lens[0], k = lens[5];
    if (bufs[5].itemsize != 8 || lens[1] != size || lens[2] != size || lens[3] != size ||
        lens[4] != size || lens[6] != k || (live && (lens[7] != size || lens[8] != size ||
                                                     bufs[8].itemsize != 8)))
        goto refuse;
    double *ev = bufs[0].buf, *touched = bufs[1].buf, *since = bufs[2].buf;
    char *first = bufs[3].buf;
    const double *seen_free = bufs[4].buf, *factor = bufs[6].buf;
    const long long *hit = bufs[5].buf;
    const int *cover = live ? bufs[7].buf : NULL;
    const long long *hit_frame = live ? bufs[8].buf : NULL;
    for (Py_ssize_t q = 0; q < k; q++)
        if (hit[q] < 0 || hit[q] >= size) goto refuse;
    for (Py_ssize_t q = 0; q < k; q++) {
        Py_ssize_t c = (Py_ssize_t)hit[q];
        double before = ev[c] * factor[q];
        int was = before >= occ;
        double after = before + add;
        if (!(after <= top || after != after)) after = top; /* np.minimum: nan stays */
        int now = after >= occ;
        ev[c] = after;
        touched[c] = stamp;
        double s = since[c];
        int kept = was && s == s; /* occupied before, and not free: since not nan */
        since[c] = kept ? s : (now ? stamp : Py_NAN);
        double seen = (live && cover[c] > 0 && hit_frame[c] != frame) ? cast_stamp : seen_free[c];
        int arrived = stamp - seen <= window;
        if (!kept) first[c] = (char)(casting && now && !arrived);
    }
    release_all(bufs, got);
    Py_RETURN_NONE;
refuse:
    release_all(bufs, got);
    Py_RETURN_NOTIMPLEMENTED;
}

/* ------------------------------------------------------------------ still_cast
 *
 * StillCast.cast's usual frame compiled (background/still_cast.py): every beam of the
 * frame (ids, increasing) already listed, its direction the listed one bit for bit or,
 * its list safe, within the tolerance per coordinate. Then every beam takes its cells from its list
 * (a listed beam not in the frame has 0 samples): the coverage gains the samples
 * [n_old, n) of a beam that reaches farther and loses [n, n_old) of one that reaches less;
 * a cell with a return that was live (covered, no return in the last frame) and a cell
 * that loses its last sample while live get the last frame's stamp in seen_free; the
 * cells with a return get this frame's number; the lists' sample counts become n.
 * Integers and stored stamps only (no arithmetic on floats but the directions'
 * differences, |u - u_listed|, compared as the Python one does), so the arrays are the
 * same as the Python one's. NotImplemented (nothing written) for every other frame and
 * for input not as expected: the Python one runs. (A cell loses its last sample only if
 * it had one: its coverage before was positive, as the Python one asks.) */

/* The coverage and stamps of a still laser's frame (see still_cast_usual), all indices
 * checked by the caller: the lists' samples go from ln to n_new (cells (nl, kk)), the
 * cells `lost` (nlost, each a sample of a list computed again) lose one each. */
static void cast_apply(const long long *n_new, const long long *ln, Py_ssize_t nl,
                       const long long *cells, Py_ssize_t kk, const long long *lost,
                       Py_ssize_t nlost, const long long *hit, Py_ssize_t nh, int *cover,
                       long long *hit_frame, double *seen_free, long long last, double stamp) {
    /* a cell with a return now that was live in the last frame: its stamp is written */
    for (Py_ssize_t q = 0; q < nh; q++) {
        long long c = hit[q];
        if (cover[c] > 0 && hit_frame[c] != last) seen_free[c] = stamp;
    }
    /* the samples gained and lost */
    for (Py_ssize_t q = 0; q < nl; q++) {
        const long long *row = cells + q * kk;
        if (n_new[q] > ln[q])
            for (long long k = ln[q]; k < n_new[q]; k++) cover[row[k]] += 1;
        else
            for (long long k = n_new[q]; k < ln[q]; k++) cover[row[k]] -= 1;
    }
    for (Py_ssize_t q = 0; q < nlost; q++) cover[lost[q]] -= 1;
    /* a cell that lost its last sample while live (no return in the last frame) */
    for (Py_ssize_t q = 0; q < nl; q++) {
        const long long *row = cells + q * kk;
        for (long long k = n_new[q]; k < ln[q]; k++) {
            long long c = row[k];
            if (cover[c] == 0 && hit_frame[c] != last) seen_free[c] = stamp;
        }
    }
    for (Py_ssize_t q = 0; q < nlost; q++) {
        long long c = lost[q];
        if (cover[c] == 0 && hit_frame[c] != last) seen_free[c] = stamp;
    }
    for (Py_ssize_t q = 0; q < nh; q++) hit_frame[hit[q]] = last + 1;
}

/* 0 when every cell of the samples between ln and n_new (each within [0, kk]), of `lost`
 * and of `hit` lies in [0, size), else 1. */
static int cast_indices_ok(const long long *n_new, const long long *ln, Py_ssize_t nl,
                           const long long *cells, Py_ssize_t kk, const long long *lost,
                           Py_ssize_t nlost, const long long *hit, Py_ssize_t nh,
                           Py_ssize_t size) {
    for (Py_ssize_t q = 0; q < nl; q++) {
        if (n_new[q] < 0 || n_new[q] > kk || ln[q] < 0 || ln[q] > kk) return 1;
        long long lo = n_new[q] < ln[q] ? n_new[q] : ln[q];
        long long hi = n_new[q] < ln[q] ? ln[q] : n_new[q];
        for (long long k = lo; k < hi; k++) {
            long long c = cells[q * kk + k];
            if (c < 0 || c >= size) return 1;
        }
    }
    for (Py_ssize_t q = 0; q < nlost; q++)
        if (lost[q] < 0 || lost[q] >= size) return 1;
    for (Py_ssize_t q = 0; q < nh; q++)
        if (hit[q] < 0 || hit[q] >= size) return 1;
    return 0;
}

static PyObject *still_cast_usual(PyObject *self, PyObject *const *args, Py_ssize_t nargs) {
    (void)self;
    if (nargs != 15) {
        PyErr_SetString(PyExc_TypeError,
                        "still_cast_usual(ids, listed, u, listed_u, n, listed_n, cells, cover, "
                        "hit_frame, seen_free, hit, safe, frame, stamp, tolerance)");
        return NULL;
    }
    long long last = PyLong_AsLongLong(args[12]);
    double stamp = PyFloat_AsDouble(args[13]), tol = PyFloat_AsDouble(args[14]);
    if (PyErr_Occurred()) return NULL;
    enum { IDS, LISTED, U, LU, N, LN, CELLS, COVER, HF, SEEN, HIT, SAFE, NBUF };
    const char *formats[NBUF] = {"l", "l", "d", "d", "l", "l", "l", "i", "l", "d", "l", "?"};
    const char *alts[NBUF] = {"q", "q", NULL, NULL, "q", "q", "q", NULL, "q", NULL, "q", NULL};
    const int writable[NBUF] = {0, 0, 0, 0, 0, 1, 0, 1, 1, 1, 0, 0};
    Py_buffer bufs[NBUF];
    Py_ssize_t lens[NBUF];
    long long *n_new = NULL;
    int got = 0;
    for (int b = 0; b < NBUF; b++) {
        if (flat_buffer(args[b], &bufs[b], formats[b], alts[b], writable[b], &lens[b]))
            goto refuse;
        got = b + 1;
        if (bufs[b].itemsize != (b == COVER ? 4 : b == SAFE ? 1 : 8)) goto refuse;
    }
    Py_ssize_t nb = lens[IDS], nl = lens[LISTED], size = lens[COVER];
    if (nb == 0 || nb > nl || lens[U] != 2 * nb || lens[LU] != 2 * nl || lens[N] != nb ||
        lens[LN] != nl || bufs[CELLS].ndim != 2 || bufs[CELLS].shape[0] != nl ||
        lens[HF] != size || lens[SEEN] != size || lens[SAFE] != nl)
        goto refuse;
    Py_ssize_t kk = bufs[CELLS].shape[1], nh = lens[HIT];
    const long long *ids = bufs[IDS].buf, *listed = bufs[LISTED].buf, *n = bufs[N].buf;
    const long long *cells = bufs[CELLS].buf, *hit = bufs[HIT].buf;
    const double *u = bufs[U].buf, *lu = bufs[LU].buf;
    long long *ln = bufs[LN].buf, *hit_frame = bufs[HF].buf;
    int *cover = bufs[COVER].buf;
    double *seen_free = bufs[SEEN].buf;
    const char *safe = bufs[SAFE].buf;
    n_new = PyMem_Calloc((size_t)nl, sizeof(long long)); /* 0: a listed beam not in the frame */
    if (!n_new) {
        release_all(bufs, got);
        return PyErr_NoMemory();
    }
    /* the usual frame? (and every index in range: nothing is written before this holds) */
    Py_ssize_t p = 0;
    for (Py_ssize_t b = 0; b < nb; b++) {
        if (b > 0 && ids[b] <= ids[b - 1]) goto refuse; /* (not increasing) */
        while (p < nl && listed[p] < ids[b]) p++;
        if (p == nl || listed[p] != ids[b]) goto refuse; /* a beam not listed */
        /* its list stands: the same direction bit for bit, or a safe one within tol */
        double dx = fabs(u[2 * b] - lu[2 * p]), dy = fabs(u[2 * b + 1] - lu[2 * p + 1]);
        if (!(dx == 0.0 && dy == 0.0) && !(safe[p] && dx <= tol && dy <= tol)) goto refuse;
        if (n[b] < 0 || n[b] > kk) goto refuse;
        n_new[p] = n[b];
    }
    if (cast_indices_ok(n_new, ln, nl, cells, kk, NULL, 0, hit, nh, size)) goto refuse;
    cast_apply(n_new, ln, nl, cells, kk, NULL, 0, hit, nh, cover, hit_frame, seen_free, last,
               stamp);
    memcpy(ln, n_new, (size_t)nl * sizeof(long long));
    PyMem_Free(n_new);
    release_all(bufs, got);
    Py_RETURN_NONE;
refuse:
    PyMem_Free(n_new);
    release_all(bufs, got);
    Py_RETURN_NOTIMPLEMENTED;
}

/* StillCast.cast's coverage and stamps of any frame compiled, once the Python one has
 * listed its beams again where needed: the lists' sample counts go from listed_n to n_new
 * (the caller keeps n_new), `lost` (or None) the cells of the old samples of the lists
 * computed again. None, or NotImplemented (nothing written) for input not as expected. */
static PyObject *still_cast_apply(PyObject *self, PyObject *const *args, Py_ssize_t nargs) {
    (void)self;
    if (nargs != 10) {
        PyErr_SetString(PyExc_TypeError,
                        "still_cast_apply(n_new, listed_n, cells, cover, hit_frame, seen_free, "
                        "hit, lost, frame, stamp)");
        return NULL;
    }
    long long last = PyLong_AsLongLong(args[8]);
    double stamp = PyFloat_AsDouble(args[9]);
    if (PyErr_Occurred()) return NULL;
    enum { NN, LN, CELLS, COVER, HF, SEEN, HIT, LOST, NBUF };
    const char *formats[NBUF] = {"l", "l", "l", "i", "l", "d", "l", "l"};
    const char *alts[NBUF] = {"q", "q", "q", NULL, "q", NULL, "q", "q"};
    const int writable[NBUF] = {0, 0, 0, 1, 1, 1, 0, 0};
    int with_lost = args[7] != Py_None;
    Py_buffer bufs[NBUF];
    Py_ssize_t lens[NBUF];
    int got = 0;
    for (int b = 0; b < (with_lost ? NBUF : NBUF - 1); b++) {
        if (flat_buffer(args[b], &bufs[b], formats[b], alts[b], writable[b], &lens[b]))
            goto refuse;
        got = b + 1;
        if (bufs[b].itemsize != (b == COVER ? 4 : 8)) goto refuse;
    }
    Py_ssize_t nl = lens[NN], size = lens[COVER];
    if (lens[LN] != nl || bufs[CELLS].ndim != 2 || bufs[CELLS].shape[0] != nl ||
        lens[HF] != size || lens[SEEN] != size)
        goto refuse;
    Py_ssize_t kk = bufs[CELLS].shape[1], nh = lens[HIT];
    Py_ssize_t nlost = with_lost ? lens[LOST] : 0;
    const long long *n_new = bufs[NN].buf, *ln = bufs[LN].buf, *cells = bufs[CELLS].buf;
    const long long *hit = bufs[HIT].buf, *lost = with_lost ? bufs[LOST].buf : NULL;
    if (cast_indices_ok(n_new, ln, nl, cells, kk, lost, nlost, hit, nh, size)) goto refuse;
    cast_apply(n_new, ln, nl, cells, kk, lost, nlost, hit, nh, bufs[COVER].buf, bufs[HF].buf,
               bufs[SEEN].buf, last, stamp);
    release_all(bufs, got);
    Py_RETURN_NONE;
refuse:
    release_all(bufs, got);
    Py_RETURN_NOTIMPLEMENTED;
}

/* ------------------------------------------------------------------ histogram_foreground
 *
 * BeamHistogramBackground.learn_foreground's frozen frame of one laser compiled
 * (background/beam_histogram.py, _foreground_and_bins and the usual case of
 * _BeamTable.relearn): each valid beam's range bin, min(trunc(range / bin_width), K - 1),
 * is foreground where it is not static; the points' foreground is their beams'. With the
 * candidates (relearning asked): where no return lies beyond its beam's nearest static bin
 * by more than `reach` bins, every valid beam's candidate ends (-1) and False is returned;
 * where one does, nothing is written to them and True is returned (the Python relearning
 * follows them). The same division and truncation as numpy's; NotImplemented (fg_out
 * untouched) for input not as expected: the Python one runs. */

static PyObject *histogram_foreground(PyObject *self, PyObject *const *args, Py_ssize_t nargs) {
    (void)self;
    if (nargs != 9) {
        PyErr_SetString(PyExc_TypeError,
                        "histogram_foreground(ranges, valid_beams, static, nearest, candidate, "
                        "bin_width, reach, point_beams, fg_out)");
        return NULL;
    }
    double bw = PyFloat_AsDouble(args[5]);
    long long reach = PyLong_AsLongLong(args[6]);
    if (PyErr_Occurred()) return NULL;
    int relearn = args[4] != Py_None;
    enum { RANGES, VALID, STATIC, NEAREST, PB, FG, CAND, NBUF };
    const int which[NBUF] = {0, 1, 2, 3, 7, 8, 4};
    const char *formats[NBUF] = {"d", "l", "?", "l", "l", "?", "l"};
    const char *alts[NBUF] = {NULL, "q", NULL, "q", "q", NULL, "q"};
    const int writable[NBUF] = {0, 0, 0, 0, 0, 1, 1};
    const Py_ssize_t items[NBUF] = {8, 8, 1, 8, 8, 1, 8};
    Py_buffer bufs[NBUF];
    Py_ssize_t lens[NBUF];
    char *fg_beam = NULL;
    int got = 0;
    for (int b = 0; b < (relearn ? NBUF : NBUF - 1); b++) {
        if (flat_buffer(args[which[b]], &bufs[b], formats[b], alts[b], writable[b], &lens[b]))
            goto refuse;
        got = b + 1;
        if (bufs[b].itemsize != items[b]) goto refuse;
    }
    Py_ssize_t n_beams = lens[RANGES], nv = lens[VALID], np_ = lens[PB];
    if (bufs[STATIC].ndim != 2 || lens[FG] != np_) goto refuse;
    Py_ssize_t rows = bufs[STATIC].shape[0], kk = bufs[STATIC].shape[1];
    if (kk < 1 || lens[NEAREST] != rows || (relearn && lens[CAND] != rows)) goto refuse;
    const double *ranges = bufs[RANGES].buf;
    const long long *valid = bufs[VALID].buf, *nearest = bufs[NEAREST].buf;
    const long long *pb = bufs[PB].buf;
    const char *stat = bufs[STATIC].buf;
    char *fg = bufs[FG].buf;
    fg_beam = PyMem_Calloc((size_t)(n_beams > 0 ? n_beams : 1), 1); /* invalid beams: 0 */
    if (!fg_beam) {
        release_all(bufs, got);
        return PyErr_NoMemory();
    }
    int beyond = 0;
    for (Py_ssize_t q = 0; q < nv; q++) {
        long long b = valid[q];
        if (b < 0 || b >= n_beams || b >= rows) goto refuse;
        double x = ranges[b] / bw;
        if (!(x >= 0.0 && x < 9e18)) goto refuse; /* (a valid range is finite, positive) */
        long long k = (long long)x;
        if (k > kk - 1) k = kk - 1;
        fg_beam[b] = !stat[b * kk + k];
        if (k > nearest[b] + reach) beyond = 1;
    }
    for (Py_ssize_t q = 0; q < np_; q++)
        if (pb[q] < 0 || pb[q] >= n_beams) goto refuse;
    for (Py_ssize_t q = 0; q < np_; q++) fg[q] = fg_beam[pb[q]];
    if (relearn && !beyond) {
        long long *cand = bufs[CAND].buf;
        for (Py_ssize_t q = 0; q < nv; q++) cand[valid[q]] = -1;
    }
    PyMem_Free(fg_beam);
    release_all(bufs, got);
    if (relearn && beyond) Py_RETURN_TRUE;
    Py_RETURN_FALSE;
refuse:
    PyMem_Free(fg_beam);
    release_all(bufs, got);
    Py_RETURN_NOTIMPLEMENTED;
}

/* ------------------------------------------------------------------ empty beams
 *
 * empty_scans.beam_kinds_python compiled: a scan's beams without a valid return counted by
 * kind in one pass, each count by the reference's own test of a beam that is not valid
 * (not finite, positive, at least range_min and at most range_max): NaN, +inf, -inf,
 * finite and negative, zero, positive and finite under range_min, over range_max. The
 * comparisons are numpy's (IEEE doubles, range_min and range_max as Python floats), so the
 * counts are the same integers. Returns the number of beams not valid; NotImplemented
 * (nothing written) for input not as expected: the Python one runs. */

static PyObject *beam_kinds(PyObject *self, PyObject *const *args, Py_ssize_t nargs) {
    (void)self;
    if (nargs != 4) {
        PyErr_SetString(PyExc_TypeError, "beam_kinds(ranges, range_min, range_max, counts_out)");
        return NULL;
    }
    if (!PyFloat_CheckExact(args[1]) || !PyFloat_CheckExact(args[2])) Py_RETURN_NOTIMPLEMENTED;
    double lo = PyFloat_AS_DOUBLE(args[1]), hi = PyFloat_AS_DOUBLE(args[2]);
    Py_buffer bufs[2];
    Py_ssize_t lens[2];
    int got = 0;
    if (flat_buffer(args[0], &bufs[0], "d", NULL, 0, &lens[0])) goto refuse;
    got = 1;
    if (flat_buffer(args[3], &bufs[1], "l", "q", 1, &lens[1])) goto refuse;
    got = 2;
    if (bufs[0].ndim != 1 || bufs[1].itemsize != 8 || lens[1] != 7) goto refuse;
    const double *r = bufs[0].buf;
    long long c[7] = {0, 0, 0, 0, 0, 0, 0}, bad = 0;
    for (Py_ssize_t q = 0; q < lens[0]; q++) {
        double x = r[q];
        int finite = isfinite(x);
        if (finite && x > 0.0 && x >= lo && x <= hi) continue;
        bad++;
        int positive = finite && x > 0.0;
        c[0] += isnan(x) != 0;
        c[1] += x == INFINITY;
        c[2] += x == -INFINITY;
        c[3] += finite && x < 0.0;
        c[4] += x == 0.0;
        c[5] += positive && x < lo;
        c[6] += positive && x > hi;
    }
    long long *out = bufs[1].buf;
    for (int k = 0; k < 7; k++) out[k] = c[k];
    release_all(bufs, got);
    return PyLong_FromLongLong(bad);
refuse:
    release_all(bufs, got);
    Py_RETURN_NOTIMPLEMENTED;
}

/* ------------------------------------------------------------------ prune
 *
 * hypothesis.prune_children compiled: a cluster's children normalised, N-scan-back and
 * ratio pruned, the same hypotheses in the same order with the same log weights. Every
 * float is made by the reference's IEEE operations in its order: logsumexp is
 * top + log(fsum(exp(v - top))) with math.fsum's algorithm (CPython's msum: exact partials,
 * rounded once), exp and log the C library's as Python's math module; the sorts are stable
 * (Python's). The weights are worked on in a C array and written to the hypotheses kept
 * only (the reference also rewrites the ones it drops, which nobody reads). Children with
 * a weight that is not finite, an N-scan ancestor that cannot be hashed, or a total that is
 * not finite return NotImplemented: the Python one takes them. */

/* math.fsum of n finite values (CPython's algorithm; no special values can occur). */
static double fsum_finite(const double *v, Py_ssize_t n, double *partials) {
    Py_ssize_t np_ = 0;
    for (Py_ssize_t k = 0; k < n; k++) {
        double x = v[k];
        Py_ssize_t i = 0;
        for (Py_ssize_t j = 0; j < np_; j++) {
            double y = partials[j];
            if (fabs(x) < fabs(y)) {
                double t = x;
                x = y;
                y = t;
            }
            double hi = x + y;
            double yr = hi - x;
            double lo = y - yr;
            if (lo != 0.0) partials[i++] = lo;
            x = hi;
        }
        np_ = i;
        if (x != 0.0) partials[np_++] = x;
    }
    double hi = 0.0;
    if (np_ > 0) {
        double lo = 0.0;
        hi = partials[--np_];
        while (np_ > 0) {
            double x = hi;
            double y = partials[--np_];
            hi = x + y;
            double yr = hi - x;
            lo = y - yr;
            if (lo != 0.0) break;
        }
        if (np_ > 0 && ((lo < 0.0 && partials[np_ - 1] < 0.0) ||
                        (lo > 0.0 && partials[np_ - 1] > 0.0))) {
            double y = lo * 2.0;
            double x = hi + y;
            double yr = x - hi;
            if (y == yr) hi = x;
        }
    }
    return hi;
}

/* hypothesis.logsumexp of w[idx[0..n-1]] (n >= 1, finite values); scratch holds 2n. */
static double logsumexp_at(const double *w, const Py_ssize_t *idx, Py_ssize_t n,
                           double *scratch) {
    double top = w[idx[0]];
    for (Py_ssize_t i = 1; i < n; i++)
        if (w[idx[i]] > top) top = w[idx[i]];
    for (Py_ssize_t i = 0; i < n; i++) scratch[i] = exp(w[idx[i]] - top);
    return top + log(fsum_finite(scratch, n, scratch + n));
}

/* hypothesis._renormalise of w[idx[0..n-1]]: 0 when the total is not finite (refused). */
static int renormalise_at(double *w, const Py_ssize_t *idx, Py_ssize_t n, double *scratch) {
    if (n == 0) return 1;
    double total = logsumexp_at(w, idx, n, scratch);
    if (!isfinite(total)) return 0;
    for (Py_ssize_t i = 0; i < n; i++) w[idx[i]] -= total;
    return 1;
}

static PyObject *log_weight_name = NULL, *ancestors_name = NULL;

static PyObject *prune(PyObject *self, PyObject *const *args, Py_ssize_t nargs) {
    (void)self;
    if (nargs != 3) {
        PyErr_SetString(PyExc_TypeError, "prune(hypotheses, depth, min_ratio)");
        return NULL;
    }
    PyObject *hyps = args[0];
    if (!PyList_Check(hyps)) {
        PyErr_SetString(PyExc_TypeError, "prune: a list of hypotheses expected");
        return NULL;
    }
    Py_ssize_t depth = PyLong_AsSsize_t(args[1]);
    if (depth == -1 && PyErr_Occurred()) return NULL;
    double min_ratio = PyFloat_AsDouble(args[2]);
    if (min_ratio == -1.0 && PyErr_Occurred()) return NULL;
    if (!log_weight_name) {
        log_weight_name = PyUnicode_InternFromString("log_weight");
        if (!log_weight_name) return NULL;
    }
    if (!ancestors_name) {
        ancestors_name = PyUnicode_InternFromString("ancestors");
        if (!ancestors_name) return NULL;
    }
    Py_ssize_t n = PyList_GET_SIZE(hyps);
    if (n == 0) return PyList_New(0);
    PyObject *out = NULL, *items = NULL, *groups = NULL;
    int refused = 0;
    /* w: weights; order, idx: index lists; scratch: 2n doubles for logsumexp */
    double *w = PyMem_Malloc(sizeof(double) * (size_t)(3 * n));
    Py_ssize_t *order = PyMem_Malloc(sizeof(Py_ssize_t) * (size_t)(3 * n));
    if (!w || !order) {
        PyErr_NoMemory();
        goto done;
    }
    double *scratch = w + n;
    Py_ssize_t *idx = order + n, *group_of = order + 2 * n;
    items = PySequence_List(hyps); /* (a copy: the callers' objects stay referenced) */
    if (!items) goto done;
    for (Py_ssize_t i = 0; i < n; i++) {
        PyObject *v = PyObject_GetAttr(PyList_GET_ITEM(items, i), log_weight_name);
        if (!v) goto done;
        w[i] = PyFloat_AsDouble(v);
        Py_DECREF(v);
        if (w[i] == -1.0 && PyErr_Occurred()) goto done;
        if (!isfinite(w[i])) {
            refused = 1;
            goto done;
        }
    }
    /* normalise_hypotheses: subtract the total, sort best first (stable) */
    for (Py_ssize_t i = 0; i < n; i++) order[i] = i;
    if (!renormalise_at(w, order, n, scratch)) {
        refused = 1;
        goto done;
    }
    for (Py_ssize_t i = 1; i < n; i++) { /* stable insertion sort by -w */
        Py_ssize_t x = order[i], j = i - 1;
        while (j >= 0 && w[order[j]] < w[x]) {
            order[j + 1] = order[j];
            j--;
        }
        order[j + 1] = x;
    }
    Py_ssize_t kept = n;
    if (depth <= 0) { /* the best one (the first of the largest) */
        Py_ssize_t best = order[0];
        for (Py_ssize_t i = 1; i < n; i++)
            if (w[order[i]] > w[best]) best = order[i];
        order[0] = best;
        kept = 1;
    } else {
        int short_history = 0;
        for (Py_ssize_t i = 0; i < n && !short_history; i++) {
            PyObject *anc = PyObject_GetAttr(PyList_GET_ITEM(items, order[i]), ancestors_name);
            if (!anc) goto done;
            if (!PyTuple_Check(anc)) {
                Py_DECREF(anc);
                refused = 1;
                goto done;
            }
            if (PyTuple_GET_SIZE(anc) < depth) short_history = 1;
            Py_DECREF(anc);
        }
        if (!short_history) { /* the groups by the ancestor depth generations back */
            groups = PyDict_New();
            if (!groups) goto done;
            Py_ssize_t n_groups = 0;
            for (Py_ssize_t i = 0; i < n; i++) {
                PyObject *anc = PyObject_GetAttr(PyList_GET_ITEM(items, order[i]),
                                                 ancestors_name);
                if (!anc) goto done;
                PyObject *key = PyTuple_GET_ITEM(anc, PyTuple_GET_SIZE(anc) - depth);
                PyObject *g = PyDict_GetItemWithError(groups, key);
                if (!g && PyErr_Occurred()) {
                    Py_DECREF(anc);
                    if (PyErr_ExceptionMatches(PyExc_TypeError)) { /* unhashable */
                        PyErr_Clear();
                        refused = 1;
                    }
                    goto done;
                }
                if (g) {
                    group_of[i] = PyLong_AsSsize_t(g);
                } else {
                    PyObject *gi = PyLong_FromSsize_t(n_groups);
                    int bad = !gi || PyDict_SetItem(groups, key, gi) < 0;
                    Py_XDECREF(gi);
                    if (bad) {
                        Py_DECREF(anc);
                        goto done;
                    }
                    group_of[i] = n_groups++;
                }
                Py_DECREF(anc);
            }
            if (n_groups > 1) { /* keep the group of the most mass (the first of them) */
                Py_ssize_t keep = -1;
                double most = 0.0;
                for (Py_ssize_t g = 0; g < n_groups; g++) {
                    Py_ssize_t m = 0;
                    for (Py_ssize_t i = 0; i < n; i++)
                        if (group_of[i] == g) idx[m++] = order[i];
                    double mass = logsumexp_at(w, idx, m, scratch);
                    if (keep < 0 || mass > most) {
                        keep = g;
                        most = mass;
                    }
                }
                Py_ssize_t m = 0;
                for (Py_ssize_t i = 0; i < n; i++)
                    if (group_of[i] == keep) order[m++] = order[i];
                kept = m;
            }
        }
    }
    if (!renormalise_at(w, order, kept, scratch)) {
        refused = 1;
        goto done;
    }
    /* ratio pruning: at least the best's weight plus log min_ratio */
    double best = w[order[0]];
    for (Py_ssize_t i = 1; i < kept; i++)
        if (w[order[i]] > best) best = w[order[i]];
    double floor_ = min_ratio > 0 ? best + log(min_ratio) : -INFINITY;
    Py_ssize_t m = 0;
    for (Py_ssize_t i = 0; i < kept; i++)
        if (w[order[i]] >= floor_) order[m++] = order[i];
    if (!renormalise_at(w, order, m, scratch)) {
        refused = 1;
        goto done;
    }
    out = PyList_New(m);
    if (!out) goto done;
    for (Py_ssize_t i = 0; i < m; i++) {
        PyObject *h = PyList_GET_ITEM(items, order[i]);
        PyObject *v = PyFloat_FromDouble(w[order[i]]);
        if (!v || PyObject_SetAttr(h, log_weight_name, v) < 0) {
            Py_XDECREF(v);
            Py_CLEAR(out);
            goto done;
        }
        Py_DECREF(v);
        PyList_SET_ITEM(out, i, Py_NewRef(h));
    }
done:
    PyMem_Free(w);
    PyMem_Free(order);
    Py_XDECREF(items);
    Py_XDECREF(groups);
    if (refused && !PyErr_Occurred()) {
        Py_XDECREF(out);
        Py_RETURN_NOTIMPLEMENTED;
    }
    return out;
}

/* ------------------------------------------------------------------ the plain MHT's children
 *
 * MHT._branch_plain's bookkeeping around the listing, compiled: `plan_plain` gathers which
 * detected children and new tracks the listed children need (the loops before
 * _make_detected_children and _new_nodes), `assemble_plain` makes the children's
 * hypotheses (MHT._assemble with models=False and _add_child, _history): the same
 * structures in the same order, the same objects looked up, the same hypotheses made by
 * calling Hypothesis(-total, tracks, history) in the same order (so the same ids), an
 * occluded child made by the tracker's own function, the weights of two children with
 * the same tracks joined by numpy's logaddexp (passed in). Children that are not what the
 * listing gives (a solution not (int, LabelledAssignment, float), labels not lists of the
 * right lengths, a measurement out of range, a parent's ancestors not a tuple) return
 * NotImplemented before anything is made: the Python code takes them. */

static PyObject *tl_name = NULL, *tm_name = NULL, *ml_name = NULL, *children_name = NULL;
static PyObject *family_name = NULL, *hyp_id_name = NULL, *minus_one = NULL;

static int plain_names(void) {
    struct {
        PyObject **slot;
        const char *text;
    } names[] = {{&tl_name, "track_label"},          {&tm_name, "track_measurement"},
                 {&ml_name, "measurement_label"},    {&children_name, "children"},
                 {&family_name, "family"},           {&hyp_id_name, "hypothesis_id"},
                 {&ancestors_name, "ancestors"},     {&log_weight_name, "log_weight"}};
    for (size_t i = 0; i < sizeof(names) / sizeof(names[0]); i++)
        if (!*names[i].slot) {
            *names[i].slot = PyUnicode_InternFromString(names[i].text);
            if (!*names[i].slot) return -1;
        }
    if (!minus_one) {
        minus_one = PyLong_FromLong(-1);
        if (!minus_one) return -1;
    }
    return 0;
}

/* One listed child, read and checked: its parent, labels (borrowed: the assignment holds
 * them) and total. */
typedef struct {
    Py_ssize_t pi;
    PyObject *tlabels, *tmeas, *mlabels; /* list, list or tuple, list */
    double total;
} Listed;

static long small_int(PyObject *v, int *ok) {
    long x = PyLong_Check(v) ? PyLong_AsLong(v) : -1;
    if (!PyLong_Check(v) || (x == -1 && PyErr_Occurred())) {
        PyErr_Clear();
        *ok = 0;
    }
    return x;
}

/* Read and check every solution: 1, 0 (not what the listing gives: NotImplemented) or -1
 * (an error). `listed` holds PyList_GET_SIZE(solutions) entries. */
static int read_solutions(PyObject *solutions, PyObject *tracks_of, Py_ssize_t m,
                          Listed *listed) {
    if (!labelled_assignment) {
        PyErr_SetString(PyExc_RuntimeError, "_clisting.setup() was not called");
        return -1;
    }
    Py_ssize_t n_sol = PyList_GET_SIZE(solutions), n_par = PyList_GET_SIZE(tracks_of);
    for (Py_ssize_t s = 0; s < n_sol; s++) {
        PyObject *sol = PyList_GET_ITEM(solutions, s);
        if (!PyTuple_CheckExact(sol) || PyTuple_GET_SIZE(sol) != 3) return 0;
        PyObject *dec = PyTuple_GET_ITEM(sol, 1);
        if ((PyObject *)Py_TYPE(dec) != labelled_assignment) return 0;
        if (!PyFloat_CheckExact(PyTuple_GET_ITEM(sol, 2))) return 0;
        int ok = 1;
        long pi = small_int(PyTuple_GET_ITEM(sol, 0), &ok);
        if (!ok || pi < 0 || pi >= n_par) return 0;
        PyObject *tracks = PyList_GET_ITEM(tracks_of, pi);
        if (!PyTuple_Check(tracks)) return 0;
        Listed *L = &listed[s];
        L->pi = pi;
        L->total = PyFloat_AS_DOUBLE(PyTuple_GET_ITEM(sol, 2));
        PyObject *v[3];
        PyObject *names[3] = {tl_name, tm_name, ml_name};
        for (int a = 0; a < 3; a++) {
            v[a] = PyObject_GetAttr(dec, names[a]);
            if (!v[a]) return -1;
            Py_DECREF(v[a]); /* (the assignment holds it) */
        }
        L->tlabels = v[0];
        L->tmeas = v[1];
        L->mlabels = v[2];
        Py_ssize_t n = PyTuple_GET_SIZE(tracks);
        if (!PyList_CheckExact(v[0]) || PyList_GET_SIZE(v[0]) != n) return 0;
        if (!(PyList_CheckExact(v[1]) || PyTuple_CheckExact(v[1])) ||
            PySequence_Fast_GET_SIZE(v[1]) != n)
            return 0;
        if (!PyList_CheckExact(v[2]) || PyList_GET_SIZE(v[2]) != m) return 0;
        PyObject **tm = PySequence_Fast_ITEMS(v[1]);
        for (Py_ssize_t i = 0; i < n; i++) {
            long label = small_int(PyList_GET_ITEM(v[0], i), &ok);
            if (!ok || label < DETECTED || label > DELETED) return 0;
            if (label == DETECTED) {
                long j = small_int(tm[i], &ok);
                if (!ok || j < 0 || j >= m) return 0;
            }
        }
        for (Py_ssize_t a = 0; a < m; a++) {
            long label = small_int(PyList_GET_ITEM(v[2], a), &ok);
            if (!ok || label < MATCHED || label > FALSE_ALARM) return 0;
        }
    }
    return 1;
}

static PyObject *plan_plain(PyObject *self, PyObject *const *args, Py_ssize_t nargs) {
    (void)self;
    if (nargs != 4) {
        PyErr_SetString(PyExc_TypeError,
                        "plan_plain(solutions, tracks_of, meas_list, measurements)");
        return NULL;
    }
    PyObject *solutions = args[0], *tracks_of = args[1], *meas_list = args[2];
    PyObject *measurements = args[3];
    if (!PyList_Check(solutions) || !PyList_Check(tracks_of) || !PyList_Check(meas_list)) {
        PyErr_SetString(PyExc_TypeError, "plan_plain: lists expected");
        return NULL;
    }
    if (plain_names() < 0) return NULL;
    Py_ssize_t n_sol = PyList_GET_SIZE(solutions), m = PyList_GET_SIZE(meas_list);
    Listed *listed = PyMem_Malloc(sizeof(Listed) * (size_t)(n_sol ? n_sol : 1));
    if (!listed) return PyErr_NoMemory();
    PyObject *seen = NULL, *pairs = NULL, *born = NULL, *result = NULL;
    int ok = read_solutions(solutions, tracks_of, m, listed);
    if (ok <= 0) goto done;
    seen = PySet_New(NULL);
    pairs = PyList_New(0);
    born = PyDict_New();
    if (!seen || !pairs || !born) goto done;
    for (Py_ssize_t s = 0; s < n_sol; s++) {
        Listed *L = &listed[s];
        PyObject *tracks = PyList_GET_ITEM(tracks_of, L->pi);
        PyObject **tm = PySequence_Fast_ITEMS(L->tmeas);
        for (Py_ssize_t i = 0; i < PyTuple_GET_SIZE(tracks); i++) {
            if (PyLong_AsLong(PyList_GET_ITEM(L->tlabels, i)) != DETECTED) continue;
            PyObject *node = PyTuple_GET_ITEM(tracks, i);
            PyObject *j = PyList_GET_ITEM(meas_list, PyLong_AsSsize_t(tm[i]));
            PyObject *node_id = PyObject_GetAttr(node, node_id_name);
            if (!node_id) goto done;
            PyObject *key = PyTuple_Pack(2, node_id, j);
            Py_DECREF(node_id);
            if (!key) goto done;
            int had = PySet_Contains(seen, key);
            if (had != 0) {
                Py_DECREF(key);
                if (had < 0) goto done;
                continue;
            }
            PyObject *kids = PyObject_GetAttr(node, children_name);
            if (!kids) {
                Py_DECREF(key);
                goto done;
            }
            int made = PySequence_Contains(kids, j);
            Py_DECREF(kids);
            if (made != 0) {
                Py_DECREF(key);
                if (made < 0) goto done;
                continue;
            }
            int bad = PySet_Add(seen, key) < 0;
            Py_DECREF(key);
            if (bad) goto done;
            PyObject *item = PyTuple_Pack(4, node, j, measurements, j);
            if (!item) goto done;
            bad = PyList_Append(pairs, item) < 0;
            Py_DECREF(item);
            if (bad) goto done;
        }
        for (Py_ssize_t a = 0; a < m; a++) {
            if (PyLong_AsLong(PyList_GET_ITEM(L->mlabels, a)) != NEW_LABEL) continue;
            PyObject *j = PyList_GET_ITEM(meas_list, a);
            int had = PyDict_Contains(born, j);
            if (had < 0) goto done;
            if (had) continue;
            PyObject *item = PyTuple_Pack(3, measurements, j, j);
            if (!item) goto done;
            int bad = PyDict_SetItem(born, j, item) < 0;
            Py_DECREF(item);
            if (bad) goto done;
        }
    }
    result = PyTuple_Pack(2, pairs, born);
done:
    PyMem_Free(listed);
    Py_XDECREF(seen);
    Py_XDECREF(pairs);
    Py_XDECREF(born);
    if (ok == 0 && !PyErr_Occurred()) Py_RETURN_NOTIMPLEMENTED;
    return result;
}

/* MHT._history: the parent's ancestors and its id, the last n_scan (none for 0). */
static PyObject *history_of(PyObject *parent, Py_ssize_t n_scan) {
    if (n_scan <= 0) return PyTuple_New(0);
    PyObject *anc = PyObject_GetAttr(parent, ancestors_name);
    if (!anc) return NULL;
    PyObject *hid = PyObject_GetAttr(parent, hyp_id_name);
    if (!hid) {
        Py_DECREF(anc);
        return NULL;
    }
    Py_ssize_t len = PyTuple_GET_SIZE(anc) + 1;
    Py_ssize_t start = len > n_scan ? len - n_scan : 0;
    PyObject *out = PyTuple_New(len - start);
    if (out) {
        for (Py_ssize_t i = start; i < len - 1; i++)
            PyTuple_SET_ITEM(out, i - start, Py_NewRef(PyTuple_GET_ITEM(anc, i)));
        PyTuple_SET_ITEM(out, len - 1 - start, Py_NewRef(hid));
    }
    Py_DECREF(anc);
    Py_DECREF(hid);
    return out;
}

static PyObject *assemble_plain(PyObject *self, PyObject *const *args, Py_ssize_t nargs) {
    (void)self;
    if (nargs != 10) {
        PyErr_SetString(PyExc_TypeError,
                        "assemble_plain(solutions, parents, tracks_of, meas_list, new_nodes, "
                        "occluded_child, stamp, Hypothesis, n_scan, logaddexp)");
        return NULL;
    }
    PyObject *solutions = args[0], *parents = args[1], *tracks_of = args[2];
    PyObject *meas_list = args[3], *new_nodes = args[4], *occluded = args[5];
    PyObject *stamp = args[6], *hyp_cls = args[7], *logaddexp = args[9];
    if (!PyList_Check(solutions) || !PyList_Check(parents) || !PyList_Check(tracks_of) ||
        !PyList_Check(meas_list) || !PyDict_Check(new_nodes)) {
        PyErr_SetString(PyExc_TypeError, "assemble_plain: lists and a dict expected");
        return NULL;
    }
    Py_ssize_t n_scan = PyLong_AsSsize_t(args[8]);
    if (n_scan == -1 && PyErr_Occurred()) return NULL;
    if (plain_names() < 0) return NULL;
    Py_ssize_t n_sol = PyList_GET_SIZE(solutions), m = PyList_GET_SIZE(meas_list);
    Py_ssize_t n_par = PyList_GET_SIZE(parents);
    if (PyList_GET_SIZE(tracks_of) != n_par) {
        PyErr_SetString(PyExc_ValueError, "parents and tracks_of differ in length");
        return NULL;
    }
    Listed *listed = PyMem_Malloc(sizeof(Listed) * (size_t)(n_sol ? n_sol : 1));
    PyObject **history = PyMem_Calloc((size_t)(n_par ? n_par : 1), sizeof(PyObject *));
    PyObject *children = NULL, *tracks = NULL;
    long long *fam = NULL;
    Py_ssize_t fam_cap = 0;
    int ok = 0;
    if (!listed || !history) {
        PyErr_NoMemory();
        goto done;
    }
    ok = read_solutions(solutions, tracks_of, m, listed);
    if (ok <= 0) goto done;
    for (Py_ssize_t p = 0; p < n_par; p++) { /* (checked before anything is made) */
        PyObject *anc = PyObject_GetAttr(PyList_GET_ITEM(parents, p), ancestors_name);
        if (!anc) goto done;
        int is_tuple = PyTuple_Check(anc);
        Py_DECREF(anc);
        if (!is_tuple) {
            ok = 0;
            goto done;
        }
    }
    children = PyDict_New();
    if (!children) goto done;
    for (Py_ssize_t s = 0; s < n_sol; s++) {
        Listed *L = &listed[s];
        PyObject *parent = PyList_GET_ITEM(parents, L->pi);
        if (!history[L->pi]) {
            history[L->pi] = history_of(parent, n_scan);
            if (!history[L->pi]) goto done;
        }
        PyObject *nodes = PyList_GET_ITEM(tracks_of, L->pi);
        PyObject **tm = PySequence_Fast_ITEMS(L->tmeas);
        tracks = PyList_New(0);
        if (!tracks) goto done;
        for (Py_ssize_t i = 0; i < PyTuple_GET_SIZE(nodes); i++) {
            long label = PyLong_AsLong(PyList_GET_ITEM(L->tlabels, i));
            if (label == DELETED) continue;
            PyObject *node = PyTuple_GET_ITEM(nodes, i);
            PyObject *kids = PyObject_GetAttr(node, children_name);
            if (!kids) goto done;
            PyObject *child;
            if (label == DETECTED) {
                PyObject *j = PyList_GET_ITEM(meas_list, PyLong_AsSsize_t(tm[i]));
                child = PyObject_GetItem(kids, j);
            } else {
                child = PyDict_Check(kids) ? PyDict_GetItemWithError(kids, minus_one) : NULL;
                if (child) {
                    Py_INCREF(child);
                } else if (!PyErr_Occurred()) {
                    PyObject *call[2] = {node, stamp};
                    child = PyObject_Vectorcall(occluded, call, 2, NULL);
                }
            }
            Py_DECREF(kids);
            if (!child) goto done;
            int bad = PyList_Append(tracks, child) < 0;
            Py_DECREF(child);
            if (bad) goto done;
        }
        int born_here = 0;
        for (Py_ssize_t a = 0; a < m; a++) {
            if (PyLong_AsLong(PyList_GET_ITEM(L->mlabels, a)) != NEW_LABEL) continue;
            PyObject *node = PyObject_GetItem(new_nodes, PyList_GET_ITEM(meas_list, a));
            if (!node) goto done;
            int bad = PyList_Append(tracks, node) < 0;
            Py_DECREF(node);
            if (bad) goto done;
            born_here = 1;
        }
        Py_ssize_t n = PyList_GET_SIZE(tracks);
        if (born_here && n > 1) { /* tracks.sort(key=BY_FAMILY): stable, by family */
            if (n > fam_cap) {
                long long *grown = PyMem_Realloc(fam, sizeof(long long) * (size_t)n);
                if (!grown) {
                    PyErr_NoMemory();
                    goto done;
                }
                fam = grown;
                fam_cap = n;
            }
            for (Py_ssize_t i = 0; i < n; i++) {
                PyObject *f = PyObject_GetAttr(PyList_GET_ITEM(tracks, i), family_name);
                if (!f) goto done;
                fam[i] = PyLong_AsLongLong(f);
                Py_DECREF(f);
                if (fam[i] == -1 && PyErr_Occurred()) goto done;
            }
            PyObject **items = ((PyListObject *)tracks)->ob_item;
            for (Py_ssize_t i = 1; i < n; i++) {
                PyObject *x = items[i];
                long long fx = fam[i];
                Py_ssize_t j = i - 1;
                while (j >= 0 && fam[j] > fx) {
                    items[j + 1] = items[j];
                    fam[j + 1] = fam[j];
                    j--;
                }
                items[j + 1] = x;
                fam[j + 1] = fx;
            }
        }
        /* _add_child: the key of the node ids; a second child of the same tracks adds its
         * probability to the first's */
        PyObject *key = PyTuple_New(n);
        if (!key) goto done;
        for (Py_ssize_t i = 0; i < n; i++) {
            PyObject *id = PyObject_GetAttr(PyList_GET_ITEM(tracks, i), node_id_name);
            if (!id) {
                Py_DECREF(key);
                goto done;
            }
            PyTuple_SET_ITEM(key, i, id);
        }
        PyObject *there = PyDict_GetItemWithError(children, key);
        if (!there && PyErr_Occurred()) {
            Py_DECREF(key);
            goto done;
        }
        PyObject *neg = PyFloat_FromDouble(-L->total);
        if (!neg) {
            Py_DECREF(key);
            goto done;
        }
        int bad;
        if (there) {
            PyObject *w = PyObject_GetAttr(there, log_weight_name);
            PyObject *joined = NULL, *as_float = NULL;
            if (w) {
                PyObject *call[2] = {w, neg};
                joined = PyObject_Vectorcall(logaddexp, call, 2, NULL);
            }
            if (joined) as_float = PyNumber_Float(joined);
            bad = !as_float || PyObject_SetAttr(there, log_weight_name, as_float) < 0;
            Py_XDECREF(w);
            Py_XDECREF(joined);
            Py_XDECREF(as_float);
        } else {
            PyObject *as_tuple = PyList_AsTuple(tracks);
            PyObject *h = NULL;
            if (as_tuple) {
                PyObject *call[3] = {neg, as_tuple, history[L->pi]};
                h = PyObject_Vectorcall(hyp_cls, call, 3, NULL);
            }
            bad = !h || PyDict_SetItem(children, key, h) < 0;
            Py_XDECREF(as_tuple);
            Py_XDECREF(h);
        }
        Py_DECREF(neg);
        Py_DECREF(key);
        Py_CLEAR(tracks);
        if (bad) goto done;
    }
done:
    if (history)
        for (Py_ssize_t p = 0; p < n_par; p++) Py_XDECREF(history[p]);
    PyMem_Free(history);
    PyMem_Free(listed);
    PyMem_Free(fam);
    Py_XDECREF(tracks);
    if (ok == 0 && !PyErr_Occurred()) {
        Py_XDECREF(children);
        Py_RETURN_NOTIMPLEMENTED;
    }
    if (PyErr_Occurred()) {
        Py_XDECREF(children);
        return NULL;
    }
    return children;
}

/* MHT._make_detected_children and MHT._new_nodes_deferred of the plain MHT (its states
 * deferred): per pair (node, j, measurements, jl) of `pairs`, in order, the detected
 * child TrackNode(new_node_id(), node.family, node.node_id, deferred, deferred, stamp,
 * detected, jl, node.hits + 1, 0, node.age + 1, loglik[row_of[node.node_id], jl], None),
 * stored as node.children[j] and appended to `made` as (child, node, jl); then per
 * measurement of `born` ({j: (measurements, j, origin)}) in increasing order the new
 * TrackNode(new_node_id(), new_family(), -1, deferred, deferred, stamp, new_label, origin),
 * appended to `births` as (node, j). Returns {j: new node}, or NotImplemented (nothing
 * made) for input the Python code takes: a node not in row_of, an index that is not an
 * int within loglik (T, M) (C-contiguous float64), a birth not keyed by its index. */
static PyObject *make_plain(PyObject *self, PyObject *const *args, Py_ssize_t nargs) {
    (void)self;
    if (nargs != 13) {
        PyErr_SetString(PyExc_TypeError,
                        "make_plain(pairs, born, loglik, row_of, TrackNode, new_node_id, "
                        "new_family, stamp, deferred, detected, new_label, made, births)");
        return NULL;
    }
    PyObject *pairs = args[0], *born = args[1], *row_of = args[3], *node_type = args[4];
    PyObject *new_id = args[5], *new_family = args[6], *stamp = args[7], *deferred = args[8];
    PyObject *detected = args[9], *new_label = args[10], *made = args[11], *births = args[12];
    if (!PyList_CheckExact(pairs) || !PyDict_CheckExact(born) || !PyDict_CheckExact(row_of) ||
        !PyList_CheckExact(made) || !PyList_CheckExact(births)) {
        PyErr_SetString(PyExc_TypeError, "make_plain: lists and dicts expected");
        return NULL;
    }
    if (plain_names() < 0) return NULL;
    static PyObject *hits_name = NULL, *age_name = NULL, *one = NULL, *zero = NULL;
    if (!hits_name && !(hits_name = PyUnicode_InternFromString("hits"))) return NULL;
    if (!age_name && !(age_name = PyUnicode_InternFromString("age"))) return NULL;
    if (!one && !(one = PyLong_FromLong(1))) return NULL;
    if (!zero && !(zero = PyLong_FromLong(0))) return NULL;
    Buf b;
    memset(&b, 0, sizeof b);
    Py_ssize_t n_pairs = PyList_GET_SIZE(pairs), n_born = PyDict_GET_SIZE(born);
    Py_ssize_t *rows = PyMem_Malloc(sizeof(Py_ssize_t) * (size_t)(n_pairs ? n_pairs : 1));
    PyObject *order = NULL, *out = NULL;
    int ok = 0;
    if (!rows) {
        PyErr_NoMemory();
        goto done;
    }
    if (PyObject_GetBuffer(args[2], &b.view, PyBUF_C_CONTIGUOUS | PyBUF_FORMAT) < 0) {
        PyErr_Clear();
        goto done;
    }
    b.held = 1;
    if (b.view.ndim != 2 || b.view.itemsize != 8 || !b.view.format ||
        strcmp(b.view.format, "d") != 0)
        goto done;
    Py_ssize_t t = b.view.shape[0], m = b.view.shape[1];
    const double *ll = b.view.buf;
    /* checked before anything is made */
    for (Py_ssize_t p = 0; p < n_pairs; p++) {
        PyObject *item = PyList_GET_ITEM(pairs, p);
        if (!PyTuple_CheckExact(item) || PyTuple_GET_SIZE(item) != 4) goto done;
        PyObject *jl = PyTuple_GET_ITEM(item, 3);
        if (!PyLong_CheckExact(jl)) goto done;
        Py_ssize_t j = PyLong_AsSsize_t(jl);
        if (j == -1 && PyErr_Occurred()) {
            PyErr_Clear();
            goto done;
        }
        PyObject *node_id = PyObject_GetAttr(PyTuple_GET_ITEM(item, 0), node_id_name);
        if (!node_id) goto done;
        PyObject *row = PyDict_GetItemWithError(row_of, node_id);
        Py_DECREF(node_id);
        if (!row) {
            PyErr_Clear();
            goto done;
        }
        Py_ssize_t r = PyLong_CheckExact(row) ? PyLong_AsSsize_t(row) : -1;
        if (r == -1) PyErr_Clear();
        if (r < 0 || r >= t || j < 0 || j >= m) goto done;
        rows[p] = r * m + j;
    }
    order = PyList_New(0);
    if (!order) goto done;
    {
        Py_ssize_t pos = 0;
        PyObject *key, *value;
        while (PyDict_Next(born, &pos, &key, &value)) {
            if (!PyTuple_CheckExact(value) || PyTuple_GET_SIZE(value) != 3) goto done;
            PyObject *j = PyTuple_GET_ITEM(value, 1);
            if (!PyLong_CheckExact(j) || PyList_Append(order, j) < 0) goto done;
        }
    }
    if (PyList_Sort(order) < 0) goto done;
    for (Py_ssize_t a = 0; a < n_born; a++) {
        PyObject *v = PyDict_GetItemWithError(born, PyList_GET_ITEM(order, a));
        if (!v) { /* (not keyed by its index: Python's KeyError) */
            PyErr_Clear();
            goto done;
        }
    }
    ok = 1;
    for (Py_ssize_t p = 0; p < n_pairs; p++) {
        PyObject *item = PyList_GET_ITEM(pairs, p);
        PyObject *node = PyTuple_GET_ITEM(item, 0), *j = PyTuple_GET_ITEM(item, 1);
        PyObject *jl = PyTuple_GET_ITEM(item, 3);
        PyObject *a[13] = {NULL};
        a[0] = PyObject_CallNoArgs(new_id);
        if (a[0]) a[1] = PyObject_GetAttr(node, family_name);
        if (a[1]) a[2] = PyObject_GetAttr(node, node_id_name);
        PyObject *hits = a[2] ? PyObject_GetAttr(node, hits_name) : NULL;
        if (hits) {
            a[8] = PyNumber_Add(hits, one);
            Py_DECREF(hits);
        }
        PyObject *age = a[8] ? PyObject_GetAttr(node, age_name) : NULL;
        if (age) {
            a[10] = PyNumber_Add(age, one);
            Py_DECREF(age);
        }
        if (a[10]) a[11] = PyFloat_FromDouble(ll[rows[p]]);
        PyObject *child = NULL;
        if (a[11]) {
            a[3] = deferred;
            a[4] = deferred;
            a[5] = stamp;
            a[6] = detected;
            a[7] = jl;
            a[9] = zero;
            a[12] = Py_None;
            child = PyObject_Vectorcall(node_type, a, 13, NULL);
        }
        Py_XDECREF(a[0]);
        Py_XDECREF(a[1]);
        Py_XDECREF(a[2]);
        Py_XDECREF(a[8]);
        Py_XDECREF(a[10]);
        Py_XDECREF(a[11]);
        if (!child) goto done;
        PyObject *kids = PyObject_GetAttr(node, children_name);
        int bad = !kids || PyObject_SetItem(kids, j, child) < 0;
        Py_XDECREF(kids);
        PyObject *entry = bad ? NULL : PyTuple_Pack(3, child, node, jl);
        bad = !entry || PyList_Append(made, entry) < 0;
        Py_XDECREF(entry);
        Py_DECREF(child);
        if (bad) goto done;
    }
    out = PyDict_New();
    if (!out) goto done;
    for (Py_ssize_t a = 0; a < n_born; a++) {
        PyObject *j = PyList_GET_ITEM(order, a);
        PyObject *v = PyDict_GetItemWithError(born, j);
        if (!v) {
            if (!PyErr_Occurred()) PyErr_SetObject(PyExc_KeyError, j);
            goto done;
        }
        PyObject *c[8] = {NULL};
        c[0] = PyObject_CallNoArgs(new_id);
        if (c[0]) c[1] = PyObject_CallNoArgs(new_family);
        PyObject *node = NULL;
        if (c[1]) {
            c[2] = minus_one;
            c[3] = deferred;
            c[4] = deferred;
            c[5] = stamp;
            c[6] = new_label;
            c[7] = PyTuple_GET_ITEM(v, 2);
            node = PyObject_Vectorcall(node_type, c, 8, NULL);
        }
        Py_XDECREF(c[0]);
        Py_XDECREF(c[1]);
        if (!node) goto done;
        PyObject *entry = PyTuple_Pack(2, node, j);
        int bad = !entry || PyDict_SetItem(out, j, node) < 0 || PyList_Append(births, entry) < 0;
        Py_XDECREF(entry);
        Py_DECREF(node);
        if (bad) goto done;
    }
done:
    PyMem_Free(rows);
    release(&b, 1);
    Py_XDECREF(order);
    if (!ok && !PyErr_Occurred()) {
        Py_XDECREF(out);
        Py_RETURN_NOTIMPLEMENTED;
    }
    if (PyErr_Occurred()) {
        Py_XDECREF(out);
        return NULL;
    }
    return out;
}

/* MHT's detection costs of a scan, core._detection_costs: out[i, j] = -(lp[i, 0] +
 * loglik[i, j]) where gated[i, j], else inf; (T, M) bools, (T, M) and (T, 3) doubles in,
 * (T, M) doubles out (C-contiguous; ValueError otherwise). The same IEEE operations as
 * numpy's `np.where(gated, -(lp[:, 0, None] + loglik), inf)`. */
static PyObject *detection_costs(PyObject *self, PyObject *const *args, Py_ssize_t nargs) {
    (void)self;
    if (nargs != 4) {
        PyErr_SetString(PyExc_TypeError, "detection_costs(gated, loglik, lp, out)");
        return NULL;
    }
    Buf b[4];
    memset(b, 0, sizeof b);
    PyObject *result = NULL;
    if (take(args[2], &b[2], 0, 0, -1, "lp") < 0 || take(args[1], &b[1], 0, 0, -1, "loglik") < 0)
        goto done;
    if (b[2].view.ndim != 2 || b[2].view.shape[1] != 3 || b[1].view.ndim != 2 ||
        b[1].view.shape[0] != b[2].view.shape[0]) {
        PyErr_SetString(PyExc_ValueError, "detection_costs: lp (T, 3), loglik (T, M) expected");
        goto done;
    }
    Py_ssize_t t = b[1].view.shape[0], m = b[1].view.shape[1];
    if (take_bools(args[0], &b[0], t * m, "gated") < 0 ||
        take(args[3], &b[3], 0, 1, t * m, "out") < 0)
        goto done;
    for (int a = 0; a < 4; a += 3)
        if (b[a].view.ndim != 2 || b[a].view.shape[0] != t || b[a].view.shape[1] != m) {
            PyErr_SetString(PyExc_ValueError, "detection_costs: gated and out (T, M) expected");
            goto done;
        }
    const char *gated = b[0].view.buf;
    const double *ll = b[1].view.buf, *lp = b[2].view.buf;
    double *out = b[3].view.buf;
    for (Py_ssize_t i = 0; i < t; i++) {
        double lp_det = lp[3 * i + DETECTED];
        for (Py_ssize_t j = 0; j < m; j++) {
            Py_ssize_t at = i * m + j;
            out[at] = gated[at] ? -(lp_det + ll[at]) : INFINITY;
        }
    }
    result = Py_NewRef(Py_None);
done:
    release(b, 4);
    return result;
}

/* ---- clustering of 2D points (clustering/compiled.py; references in single_linkage.py and
 * mean_shift.py) ---- */

/* Union-find root with path halving; parent indices, the smaller root wins a union, so a
 * root is its component's smallest member. */
static Py_ssize_t uf_find(Py_ssize_t *parent, Py_ssize_t i) {
    while (parent[i] != i) {
        parent[i] = parent[parent[i]];
        i = parent[i];
    }
    return i;
}

static void uf_union(Py_ssize_t *parent, Py_ssize_t a, Py_ssize_t b) {
    a = uf_find(parent, a);
    b = uf_find(parent, b);
    if (a < b)
        parent[b] = a;
    else if (b < a)
        parent[a] = b;
}

typedef struct {
    double x;
    Py_ssize_t i;
} XKey;

static int cmp_xkey(const void *pa, const void *pb) {
    const XKey *a = pa, *b = pb;
    if (a->x < b->x) return -1;
    if (a->x > b->x) return 1;
    return (a->i > b->i) - (a->i < b->i);
}

/* Links every pair of the m points xy (x0, y0, x1, ...) closer than `reach` (strictly when
 * `strict`, else within) in `parent` (m,), by a sweep along the axis on which the points
 * spread farther (the points sorted by that coordinate, each compared with the following
 * ones until it differs by more than `reach`). */
static int link_pairs(const double *xy, Py_ssize_t m, double reach, int strict,
                      Py_ssize_t *parent) {
    for (Py_ssize_t i = 0; i < m; i++) parent[i] = i;
    if (m < 2) return 0;
    XKey *keys = PyMem_Malloc((size_t)m * sizeof(XKey));
    if (!keys) {
        PyErr_NoMemory();
        return -1;
    }
    double lo[2] = {xy[0], xy[1]}, hi[2] = {xy[0], xy[1]};
    for (Py_ssize_t i = 1; i < m; i++)
        for (int k = 0; k < 2; k++) {
            if (xy[2 * i + k] < lo[k]) lo[k] = xy[2 * i + k];
            if (xy[2 * i + k] > hi[k]) hi[k] = xy[2 * i + k];
        }
    int ax = hi[1] - lo[1] > hi[0] - lo[0]; /* the sweep's axis; the other is `ot` */
    int ot = 1 - ax;
    for (Py_ssize_t i = 0; i < m; i++) {
        keys[i].x = xy[2 * i + ax];
        keys[i].i = i;
    }
    qsort(keys, (size_t)m, sizeof(XKey), cmp_xkey);
    double r2 = reach * reach;
    for (Py_ssize_t a = 0; a < m; a++) {
        Py_ssize_t i = keys[a].i;
        double si = xy[2 * i + ax], oi = xy[2 * i + ot];
        for (Py_ssize_t b = a + 1; b < m; b++) {
            double ds = keys[b].x - si;
            if (ds > reach) break;
            Py_ssize_t j = keys[b].i;
            double dt = xy[2 * j + ot] - oi;
            double d2 = ds * ds + dt * dt;
            if (strict ? d2 < r2 : d2 <= r2) uf_union(parent, i, j);
        }
    }
    PyMem_Free(keys);
    return 0;
}

/* single_linkage.single_linkage_python's labels: points (N, 2) doubles, mask (N,) bools or
 * None, distance, min_points, labels_out (N,) int64 written (-1: not clustered or in a
 * cluster of fewer than min_points). Points closer than `distance` are linked; labels
 * number the kept clusters by their first point. */
static PyObject *single_linkage_labels(PyObject *self, PyObject *const *args,
                                       Py_ssize_t nargs) {
    (void)self;
    if (nargs != 5) {
        PyErr_SetString(PyExc_TypeError,
                        "single_linkage_labels(points, mask, distance, min_points, labels_out)");
        return NULL;
    }
    Buf b[3];
    memset(b, 0, sizeof b);
    PyObject *result = NULL;
    Py_ssize_t *parent = NULL, *size = NULL, *idx = NULL;
    double *sub = NULL;
    double distance = PyFloat_AsDouble(args[2]);
    long long min_points = PyLong_AsLongLong(args[3]);
    if (PyErr_Occurred()) goto done;
    if (take(args[4], &b[2], 1, 1, -1, "labels_out") < 0) goto done;
    Py_ssize_t n = b[2].view.len / 8;
    if (take(args[0], &b[0], 0, 0, 2 * n, "points") < 0) goto done;
    if (args[1] != Py_None && take_bools(args[1], &b[1], n, "mask") < 0) goto done;
    const double *pts = b[0].view.buf;
    const char *mask = args[1] != Py_None ? b[1].view.buf : NULL;
    long long *labels = b[2].view.buf;
    size_t ni = (size_t)(n ? n : 1) * sizeof(Py_ssize_t);
    parent = PyMem_Malloc(ni);
    size = PyMem_Malloc(ni);
    idx = PyMem_Malloc(ni);
    sub = PyMem_Malloc((size_t)(n ? 2 * n : 1) * sizeof(double));
    if (!parent || !size || !idx || !sub) {
        PyErr_NoMemory();
        goto done;
    }
    /* the chosen points (mask and finite), in order */
    Py_ssize_t m = 0;
    for (Py_ssize_t i = 0; i < n; i++) {
        labels[i] = -1;
        double x = pts[2 * i], y = pts[2 * i + 1];
        if ((mask && !mask[i]) || !isfinite(x) || !isfinite(y)) continue;
        sub[2 * m] = x;
        sub[2 * m + 1] = y;
        idx[m++] = i;
    }
    if (link_pairs(sub, m, distance, 1, parent) < 0) goto done;
    for (Py_ssize_t i = 0; i < m; i++) size[i] = 0;
    for (Py_ssize_t i = 0; i < m; i++) size[uf_find(parent, i)]++;
    /* a root is its component's first point: there its size becomes its label (the kept
     * components numbered in order), read by the later members */
    Py_ssize_t next = 0;
    for (Py_ssize_t i = 0; i < m; i++) {
        Py_ssize_t r = uf_find(parent, i);
        if (r == i) size[i] = size[i] >= min_points ? next++ : -1;
        labels[idx[i]] = size[r];
    }
    result = Py_NewRef(Py_None);
done:
    PyMem_Free(parent);
    PyMem_Free(size);
    PyMem_Free(idx);
    PyMem_Free(sub);
    release(b, 3);
    return result;
}

/* mean_shift.cluster_covariances_python's sums: points (N, 2), labels (N,) int64 in 0..C-1,
 * mean_out (C, 2), cov_out (C, 2, 2) and count_out (C,) int64 written: per cluster the mean,
 * the covariance (divided by the size) and the size, each sum over the points in order from
 * 0.0 as numpy's bincount adds them (an empty cluster: mean and covariance 0). NotImplemented
 * (nothing written) for a label outside 0..C-1. */
static PyObject *cluster_stats(PyObject *self, PyObject *const *args, Py_ssize_t nargs) {
    (void)self;
    if (nargs != 5) {
        PyErr_SetString(PyExc_TypeError,
                        "cluster_stats(points, labels, mean_out, cov_out, count_out)");
        return NULL;
    }
    Buf b[5];
    memset(b, 0, sizeof b);
    PyObject *result = NULL;
    if (take(args[1], &b[1], 1, 0, -1, "labels") < 0 ||
        take(args[4], &b[4], 1, 1, -1, "count_out") < 0)
        goto done;
    Py_ssize_t n = b[1].view.len / 8, c = b[4].view.len / 8;
    if (take(args[0], &b[0], 0, 0, 2 * n, "points") < 0 ||
        take(args[2], &b[2], 0, 1, 2 * c, "mean_out") < 0 ||
        take(args[3], &b[3], 0, 1, 4 * c, "cov_out") < 0)
        goto done;
    const double *pts = b[0].view.buf;
    const long long *lab = b[1].view.buf;
    double *mean = b[2].view.buf, *cov = b[3].view.buf;
    long long *cnt = b[4].view.buf;
    for (Py_ssize_t i = 0; i < n; i++)
        if (lab[i] < 0 || lab[i] >= c) {
            result = Py_NewRef(Py_NotImplemented);
            goto done;
        }
    for (Py_ssize_t k = 0; k < c; k++) {
        cnt[k] = 0;
        mean[2 * k] = mean[2 * k + 1] = 0.0;
        cov[4 * k] = cov[4 * k + 1] = cov[4 * k + 2] = cov[4 * k + 3] = 0.0;
    }
    for (Py_ssize_t i = 0; i < n; i++) {
        long long k = lab[i];
        cnt[k]++;
        mean[2 * k] += pts[2 * i];
        mean[2 * k + 1] += pts[2 * i + 1];
    }
    for (Py_ssize_t k = 0; k < c; k++) {
        double safe = cnt[k] > 0 ? (double)cnt[k] : 1.0;
        mean[2 * k] /= safe;
        mean[2 * k + 1] /= safe;
    }
    for (Py_ssize_t i = 0; i < n; i++) {
        long long k = lab[i];
        double dx = pts[2 * i] - mean[2 * k], dy = pts[2 * i + 1] - mean[2 * k + 1];
        cov[4 * k] += dx * dx;
        cov[4 * k + 1] += dx * dy;
        cov[4 * k + 3] += dy * dy;
    }
    for (Py_ssize_t k = 0; k < c; k++) {
        double safe = cnt[k] > 0 ? (double)cnt[k] : 1.0;
        cov[4 * k] /= safe;
        cov[4 * k + 1] /= safe;
        cov[4 * k + 2] = cov[4 * k + 1];
        cov[4 * k + 3] /= safe;
    }
    result = Py_NewRef(Py_None);
done:
    release(b, 5);
    return result;
}

/* The mean of the points of pts (N, 2) within `bw2` (squared) of (x, y), in *ox, *oy, summed
 * in the points' order; (x, y) itself when none is. The dense kernel of mean_shift._shift. */
static void flat_mean(const double *pts, Py_ssize_t n, double x, double y, double bw2,
                      double *ox, double *oy) {
    double sx = 0.0, sy = 0.0;
    Py_ssize_t k = 0;
    for (Py_ssize_t j = 0; j < n; j++) {
        double dx = x - pts[2 * j], dy = y - pts[2 * j + 1];
        if (dx * dx + dy * dy <= bw2) {
            sx += pts[2 * j];
            sy += pts[2 * j + 1];
            k++;
        }
    }
    if (k > 0) {
        *ox = sx / (double)k;
        *oy = sy / (double)k;
    } else {
        *ox = x;
        *oy = y;
    }
}

/* mean_shift.mean_shift_python with the dense kernel: points (N, 2) (N >= 1; NotImplemented
 * when one is not finite),
 * bandwidth, tol, max_iter, merge radius, labels_out (N,) int64 and centres_out (N, 2)
 * written; returns (clusters C, iterations) (the first C rows of centres_out are the
 * modes). Each estimate moves to the mean of the points within the bandwidth of it until
 * it moves at most tol; estimates at one position are shifted once per iteration; the
 * distinct final modes within the merge radius of each other, in a chain, are one cluster,
 * numbered by first point. */
static PyObject *mean_shift_dense(PyObject *self, PyObject *const *args, Py_ssize_t nargs) {
    (void)self;
    if (nargs != 7) {
        PyErr_SetString(PyExc_TypeError,
                        "mean_shift_dense(points, bandwidth, tol, max_iter, radius, labels_out, "
                        "centres_out)");
        return NULL;
    }
    Buf b[3];
    memset(b, 0, sizeof b);
    PyObject *result = NULL;
    double *modes = NULL, *reps = NULL, *news = NULL;
    Py_ssize_t *members = NULL, *owner = NULL, *parent = NULL, *first = NULL;
    double bandwidth = PyFloat_AsDouble(args[1]), tol = PyFloat_AsDouble(args[2]);
    long long max_iter = PyLong_AsLongLong(args[3]);
    double radius = PyFloat_AsDouble(args[4]);
    if (PyErr_Occurred()) goto done;
    if (take(args[5], &b[1], 1, 1, -1, "labels_out") < 0) goto done;
    Py_ssize_t n = b[1].view.len / 8;
    if (n < 1) {
        PyErr_SetString(PyExc_ValueError, "mean_shift_dense: no points");
        goto done;
    }
    if (take(args[0], &b[0], 0, 0, 2 * n, "points") < 0 ||
        take(args[6], &b[2], 0, 1, 2 * n, "centres_out") < 0)
        goto done;
    const double *pts = b[0].view.buf;
    long long *labels = b[1].view.buf;
    double *centres = b[2].view.buf;
    for (Py_ssize_t i = 0; i < 2 * n; i++)
        if (!isfinite(pts[i])) {
            result = Py_NewRef(Py_NotImplemented);
            goto done;
        }
    size_t nd = (size_t)n * 2 * sizeof(double), ni = (size_t)n * sizeof(Py_ssize_t);
    modes = PyMem_Malloc(nd);
    reps = PyMem_Malloc(nd);
    news = PyMem_Malloc(nd);
    members = PyMem_Malloc(ni);
    owner = PyMem_Malloc(ni);
    parent = PyMem_Malloc(ni);
    first = PyMem_Malloc(ni);
    if (!modes || !reps || !news || !members || !owner || !parent || !first) {
        PyErr_NoMemory();
        goto done;
    }
    double bw2 = bandwidth * bandwidth;
    /* the first step of every estimate, each at its own point */
    Py_ssize_t m = 0;
    for (Py_ssize_t i = 0; i < n; i++) {
        double x = pts[2 * i], y = pts[2 * i + 1];
        flat_mean(pts, n, x, y, bw2, &modes[2 * i], &modes[2 * i + 1]);
        if (hypot(modes[2 * i] - x, modes[2 * i + 1] - y) > tol) members[m++] = i;
    }
    long long it = 1;
    while (m > 0 && it < max_iter) {
        it++;
        /* the distinct positions of the moving estimates, each shifted once */
        Py_ssize_t u = 0;
        for (Py_ssize_t a = 0; a < m; a++) {
            double x = modes[2 * members[a]], y = modes[2 * members[a] + 1];
            Py_ssize_t r = 0;
            while (r < u && !(reps[2 * r] == x && reps[2 * r + 1] == y)) r++;
            if (r == u) {
                reps[2 * u] = x;
                reps[2 * u + 1] = y;
                flat_mean(pts, n, x, y, bw2, &news[2 * u], &news[2 * u + 1]);
                u++;
            }
            owner[a] = r;
        }
        Py_ssize_t kept = 0;
        for (Py_ssize_t a = 0; a < m; a++) {
            Py_ssize_t i = members[a], r = owner[a];
            modes[2 * i] = news[2 * r];
            modes[2 * i + 1] = news[2 * r + 1];
            if (hypot(news[2 * r] - reps[2 * r], news[2 * r + 1] - reps[2 * r + 1]) > tol)
                members[kept++] = i;
        }
        m = kept;
    }
    /* clusters: the distinct modes (first[i]: the first estimate at i's mode) linked within
     * the merge radius */
    Py_ssize_t u = 0;
    for (Py_ssize_t i = 0; i < n; i++) {
        double x = modes[2 * i], y = modes[2 * i + 1];
        Py_ssize_t r = 0;
        while (r < u && !(reps[2 * r] == x && reps[2 * r + 1] == y)) r++;
        if (r == u) {
            reps[2 * u] = x;
            reps[2 * u + 1] = y;
            u++;
        }
        owner[i] = r;
    }
    if (link_pairs(reps, u, radius, 0, parent) < 0) goto done;
    /* numbered by first point: first[root] is the root's label once seen, -1 before */
    for (Py_ssize_t r = 0; r < u; r++) first[r] = -1;
    long long c = 0;
    for (Py_ssize_t i = 0; i < n; i++) {
        Py_ssize_t root = uf_find(parent, owner[i]);
        if (first[root] < 0) first[root] = c++;
        labels[i] = first[root];
    }
    for (long long k = 0; k < c; k++) {
        centres[2 * k] = centres[2 * k + 1] = 0.0;
        members[k] = 0;
    }
    for (Py_ssize_t i = 0; i < n; i++) {
        long long k = labels[i];
        centres[2 * k] += modes[2 * i];
        centres[2 * k + 1] += modes[2 * i + 1];
        members[k]++;
    }
    for (long long k = 0; k < c; k++) {
        centres[2 * k] /= (double)members[k];
        centres[2 * k + 1] /= (double)members[k];
    }
    result = Py_BuildValue("(LL)", c, it);
done:
    PyMem_Free(modes);
    PyMem_Free(reps);
    PyMem_Free(news);
    PyMem_Free(members);
    PyMem_Free(owner);
    PyMem_Free(parent);
    PyMem_Free(first);
    release(b, 3);
    return result;
}

/* The links between the clusters of two point sets (feet.StepDetector.events;
 * clustering/links.py's cluster_links_python): points (N, 2) with labels (N,) in 0..C-1,
 * old (M, 2) with old_labels (M,) in 0..width-1, reach; out (C * width,) int64 gets the
 * distinct keys label * width + old_label of every pair of points within reach, ascending;
 * their number returned. The old points are sorted by x once; each point is compared with
 * those within reach of its x. NotImplemented (nothing written) for a label out of range
 * or a point that is not finite. */
static PyObject *cluster_links(PyObject *self, PyObject *const *args, Py_ssize_t nargs) {
    (void)self;
    if (nargs != 7) {
        PyErr_SetString(PyExc_TypeError,
                        "cluster_links(points, labels, old, old_labels, reach, width, out)");
        return NULL;
    }
    Buf b[5];
    memset(b, 0, sizeof b);
    PyObject *result = NULL;
    XKey *keys = NULL;
    char *seen = NULL;
    double reach = PyFloat_AsDouble(args[4]);
    Py_ssize_t width = PyLong_AsSsize_t(args[5]);
    if (PyErr_Occurred()) goto done;
    if (take(args[1], &b[1], 1, 0, -1, "labels") < 0 ||
        take(args[3], &b[3], 1, 0, -1, "old_labels") < 0 ||
        take(args[6], &b[4], 1, 1, -1, "out") < 0)
        goto done;
    Py_ssize_t n = b[1].view.len / 8, m = b[3].view.len / 8, size = b[4].view.len / 8;
    if (take(args[0], &b[0], 0, 0, 2 * n, "points") < 0 ||
        take(args[2], &b[2], 0, 0, 2 * m, "old") < 0)
        goto done;
    if (width < 1 || size % width != 0) {
        PyErr_SetString(PyExc_ValueError, "cluster_links: out must hold C * width keys");
        goto done;
    }
    Py_ssize_t c = size / width;
    const double *p = b[0].view.buf, *q = b[2].view.buf;
    const long long *lab = b[1].view.buf, *old_lab = b[3].view.buf;
    long long *out = b[4].view.buf;
    for (Py_ssize_t i = 0; i < n; i++)
        if (lab[i] < 0 || lab[i] >= c || !isfinite(p[2 * i]) || !isfinite(p[2 * i + 1])) {
            result = Py_NewRef(Py_NotImplemented);
            goto done;
        }
    for (Py_ssize_t j = 0; j < m; j++)
        if (old_lab[j] < 0 || old_lab[j] >= width || !isfinite(q[2 * j]) ||
            !isfinite(q[2 * j + 1])) {
            result = Py_NewRef(Py_NotImplemented);
            goto done;
        }
    keys = PyMem_Malloc((size_t)(m ? m : 1) * sizeof(XKey));
    seen = PyMem_Calloc((size_t)(size ? size : 1), 1);
    if (!keys || !seen) {
        PyErr_NoMemory();
        goto done;
    }
    for (Py_ssize_t j = 0; j < m; j++) {
        keys[j].x = q[2 * j];
        keys[j].i = j;
    }
    qsort(keys, (size_t)m, sizeof(XKey), cmp_xkey);
    double r2 = reach * reach;
    for (Py_ssize_t i = 0; i < n; i++) {
        double x = p[2 * i], y = p[2 * i + 1];
        /* the first old point with x >= x - reach */
        Py_ssize_t lo = 0, hi = m;
        while (lo < hi) {
            Py_ssize_t mid = lo + (hi - lo) / 2;
            if (keys[mid].x < x - reach)
                lo = mid + 1;
            else
                hi = mid;
        }
        long long row = lab[i] * (long long)width;
        for (Py_ssize_t a = lo; a < m && keys[a].x - x <= reach; a++) {
            Py_ssize_t j = keys[a].i;
            double dx = x - q[2 * j], dy = y - q[2 * j + 1];
            if (dx * dx + dy * dy <= r2) seen[row + old_lab[j]] = 1;
        }
    }
    Py_ssize_t k = 0;
    for (Py_ssize_t key = 0; key < size; key++)
        if (seen[key]) out[k++] = key;
    result = PyLong_FromSsize_t(k);
done:
    PyMem_Free(keys);
    PyMem_Free(seen);
    release(b, 5);
    return result;
}

/* Each query's nearest reference point (clustering/trees.py's nearest_python, a KD-tree's
 * query with k=1): queries (N, 2), refs (M, 2) (M >= 1), index_out (N,) int64 and
 * dist_out (N,) doubles written: the index of the nearest reference (the first of equally
 * near ones) and its distance sqrt(dx^2 + dy^2) (m). NotImplemented (nothing written) for
 * a value that is not finite. */
static PyObject *nearest_points(PyObject *self, PyObject *const *args, Py_ssize_t nargs) {
    (void)self;
    if (nargs != 4) {
        PyErr_SetString(PyExc_TypeError, "nearest_points(queries, refs, index_out, dist_out)");
        return NULL;
    }
    Buf b[4];
    memset(b, 0, sizeof b);
    PyObject *result = NULL;
    if (take(args[2], &b[2], 1, 1, -1, "index_out") < 0) goto done;
    Py_ssize_t n = b[2].view.len / 8;
    if (take(args[0], &b[0], 0, 0, 2 * n, "queries") < 0 ||
        take(args[3], &b[3], 0, 1, n, "dist_out") < 0 ||
        take(args[1], &b[1], 0, 0, -1, "refs") < 0)
        goto done;
    Py_ssize_t m = b[1].view.len / 16;
    if (m < 1 || b[1].view.len != 16 * m) {
        PyErr_SetString(PyExc_ValueError, "nearest_points: refs (M, 2), M >= 1, expected");
        goto done;
    }
    const double *q = b[0].view.buf, *r = b[1].view.buf;
    long long *idx = b[2].view.buf;
    double *dist = b[3].view.buf;
    for (Py_ssize_t i = 0; i < 2 * n; i++)
        if (!isfinite(q[i])) {
            result = Py_NewRef(Py_NotImplemented);
            goto done;
        }
    for (Py_ssize_t j = 0; j < 2 * m; j++)
        if (!isfinite(r[j])) {
            result = Py_NewRef(Py_NotImplemented);
            goto done;
        }
    for (Py_ssize_t i = 0; i < n; i++) {
        double x = q[2 * i], y = q[2 * i + 1], best = INFINITY;
        Py_ssize_t at = 0;
        for (Py_ssize_t j = 0; j < m; j++) {
            double dx = r[2 * j] - x, dy = r[2 * j + 1] - y;
            double d2 = dx * dx + dy * dy;
            if (d2 < best) {
                best = d2;
                at = j;
            }
        }
        idx[i] = at;
        dist[i] = sqrt(best);
    }
    result = Py_NewRef(Py_None);
done:
    release(b, 4);
    return result;
}

/* The pairs of points within `radius` of each other (clustering/trees.py's
 * close_pairs_python, a KD-tree's query_pairs): points (N, 2), out (N (N - 1) / 2, 2) int64
 * gets the pairs (i, j), i < j, with dx^2 + dy^2 <= radius^2, in order of i then j; their
 * number returned. NotImplemented (nothing written) for a point that is not finite. */
static PyObject *close_pairs(PyObject *self, PyObject *const *args, Py_ssize_t nargs) {
    (void)self;
    if (nargs != 3) {
        PyErr_SetString(PyExc_TypeError, "close_pairs(points, radius, out)");
        return NULL;
    }
    Buf b[2];
    memset(b, 0, sizeof b);
    PyObject *result = NULL;
    double radius = PyFloat_AsDouble(args[1]);
    if (PyErr_Occurred()) goto done;
    if (take(args[0], &b[0], 0, 0, -1, "points") < 0) goto done;
    Py_ssize_t n = b[0].view.len / 16;
    if (b[0].view.len != 16 * n) {
        PyErr_SetString(PyExc_ValueError, "close_pairs: points (N, 2) expected");
        goto done;
    }
    if (take(args[2], &b[1], 1, 1, n * (n - 1), "out") < 0) goto done;
    const double *p = b[0].view.buf;
    long long *out = b[1].view.buf;
    for (Py_ssize_t i = 0; i < 2 * n; i++)
        if (!isfinite(p[i])) {
            result = Py_NewRef(Py_NotImplemented);
            goto done;
        }
    double r2 = radius * radius;
    Py_ssize_t k = 0;
    for (Py_ssize_t i = 0; i < n; i++)
        for (Py_ssize_t j = i + 1; j < n; j++) {
            double dx = p[2 * i] - p[2 * j], dy = p[2 * i + 1] - p[2 * j + 1];
            if (dx * dx + dy * dy <= r2) {
                out[2 * k] = i;
                out[2 * k + 1] = j;
                k++;
            }
        }
    result = PyLong_FromSsize_t(k);
done:
    release(b, 2);
    return result;
}

static PyMethodDef methods[] = {
    {"list_children", (PyCFunction)(void (*)(void))list_children, METH_FASTCALL,
     "list_children(priors, rows, tm, c_occ, c_del, c_new, c_fal, k, max_gap, limit, "
     "shortcut, budget): listing.list_children's children, None, or NotImplemented for a "
     "call the Python listing takes (the shortcut, a NaN prior, k < 1)."},
    {"k_best_plain", (PyCFunction)(void (*)(void))k_best_plain, METH_FASTCALL,
     "k_best_plain(tracks_of, priors, row_of, cost_live, meas_idx, occ_all, del_all, "
     "new_all, fal_all, k, max_gap, shortcut, max_cluster_size): MHT._k_best of the plain "
     "MHT on the scan's tables, as (children, cluster size), or NotImplemented for a "
     "cluster its Python path takes."},
    {"components", (PyCFunction)(void (*)(void))components, METH_FASTCALL,
     "components(fam_meas, links, n_meas): core.components_python's components, or "
     "NotImplemented for input the Python one takes (and refuses)."},
    {"static_few", (PyCFunction)(void (*)(void))static_few, METH_FASTCALL,
     "static_few(evidence, touched, since, first_sight, o0, o1, xy, resolution, n, stamp, "
     "decay_time, threshold, hold, extra, near): OccupancyGrid._static_few_python's "
     "values, or NotImplemented where it decides otherwise."},
    {"grid_hits", (PyCFunction)(void (*)(void))grid_hits, METH_FASTCALL,
     "grid_hits(points, touched, o0, o1, resolution, stamp, decay_time, hit_out, "
     "exponent_out): OccupancyGrid._hits_python's cells written to hit_out and their decay "
     "exponents to exponent_out, their number returned, or NotImplemented where the Python "
     "one runs."},
    {"grid_frame", (PyCFunction)(void (*)(void))grid_frame, METH_FASTCALL,
     "grid_frame(points, ids, ox, oy, r_out): the returns' distances from one sensor "
     "position written to r_out, and (their largest, whether the ids increase), or "
     "NotImplemented where a value is not finite (the Python one filters first)."},
    {"grid_mark", (PyCFunction)(void (*)(void))grid_mark, METH_FASTCALL,
     "grid_mark(evidence, touched, since, first_sight, seen_free, hit, factor, stamp, "
     "occupied, hit_evidence, max_evidence, arrival_window, casting, cover, hit_frame, frame, "
     "cast_stamp): OccupancyGrid._mark_hits_python's update of the cells hit, None, or "
     "NotImplemented (nothing written) where the Python one runs."},
    {"still_cast_usual", (PyCFunction)(void (*)(void))still_cast_usual, METH_FASTCALL,
     "still_cast_usual(ids, listed, u, listed_u, n, listed_n, cells, cover, hit_frame, "
     "seen_free, hit, safe, frame, stamp, tolerance): StillCast.cast's usual frame "
     "(None), or NotImplemented (nothing written) where the Python one runs."},
    {"still_cast_apply", (PyCFunction)(void (*)(void))still_cast_apply, METH_FASTCALL,
     "still_cast_apply(n_new, listed_n, cells, cover, hit_frame, seen_free, hit, lost, frame, "
     "stamp): StillCast.cast's coverage and stamps once its beams are listed (None), or "
     "NotImplemented (nothing written) where the Python one runs."},
    {"histogram_foreground", (PyCFunction)(void (*)(void))histogram_foreground,
     METH_FASTCALL,
     "histogram_foreground(ranges, valid_beams, static, nearest, candidate, bin_width, reach, "
     "point_beams, fg_out): the points' foreground of a frozen beam histogram's frame of one "
     "laser written to fg_out, and whether a return lies beyond its static world (True: the "
     "candidates untouched), or NotImplemented where the Python one runs."},
    {"beam_kinds", (PyCFunction)(void (*)(void))beam_kinds, METH_FASTCALL,
     "beam_kinds(ranges, range_min, range_max, counts_out): empty_scans.beam_kinds_python's "
     "counts written to counts_out (7,) and the number of beams not valid returned, or "
     "NotImplemented (nothing written) where the Python one runs."},
    {"prune", (PyCFunction)(void (*)(void))prune, METH_FASTCALL,
     "prune(hypotheses, depth, min_ratio): hypothesis.prune_children's hypotheses (their log "
     "weights set), or NotImplemented for children the Python one takes (a weight or a "
     "total not finite, an ancestor that cannot be hashed)."},
    {"plan_plain", (PyCFunction)(void (*)(void))plan_plain, METH_FASTCALL,
     "plan_plain(solutions, tracks_of, meas_list, measurements): MHT._branch_plain's "
     "detected children to make, [(node, j, measurements, j)], and new tracks, {j: "
     "(measurements, j, j)}, or NotImplemented for solutions the Python code takes."},
    {"assemble_plain", (PyCFunction)(void (*)(void))assemble_plain, METH_FASTCALL,
     "assemble_plain(solutions, parents, tracks_of, meas_list, new_nodes, occluded_child, "
     "stamp, Hypothesis, n_scan, logaddexp): MHT._assemble's children (models=False) by "
     "their node ids, before pruning, or NotImplemented for solutions the Python code takes."},
    {"make_plain", (PyCFunction)(void (*)(void))make_plain, METH_FASTCALL,
     "make_plain(pairs, born, loglik, row_of, TrackNode, new_node_id, new_family, stamp, "
     "deferred, detected, new_label, made, births): MHT._make_detected_children and "
     "MHT._new_nodes_deferred of the plain MHT, the new nodes by index, or NotImplemented "
     "(nothing made) for input the Python code takes."},
    {"detection_costs", (PyCFunction)(void (*)(void))detection_costs, METH_FASTCALL,
     "detection_costs(gated, loglik, lp, out): core._detection_costs of a scan written to "
     "out (T, M): -(lp[:, 0] + loglik) where gated, inf elsewhere."},
    {"single_linkage_labels", (PyCFunction)(void (*)(void))single_linkage_labels,
     METH_FASTCALL,
     "single_linkage_labels(points, mask, distance, min_points, labels_out): "
     "single_linkage.single_linkage_python's labels written to labels_out (None)."},
    {"cluster_stats", (PyCFunction)(void (*)(void))cluster_stats, METH_FASTCALL,
     "cluster_stats(points, labels, mean_out, cov_out, count_out): "
     "mean_shift.cluster_covariances_python's means, covariances and sizes written (None), "
     "or NotImplemented (nothing written) for a label outside 0..C-1."},
    {"mean_shift_dense", (PyCFunction)(void (*)(void))mean_shift_dense, METH_FASTCALL,
     "mean_shift_dense(points, bandwidth, tol, max_iter, radius, labels_out, centres_out): "
     "mean_shift.mean_shift_python's labels and centres (the first C rows) written, "
     "(C, iterations) returned, or NotImplemented (a point not finite)."},
    {"cluster_links", (PyCFunction)(void (*)(void))cluster_links, METH_FASTCALL,
     "cluster_links(points, labels, old, old_labels, reach, width, out): "
     "links.cluster_links_python's keys written to out, their number returned, or "
     "NotImplemented (nothing written) for a label out of range or a point not finite."},
    {"nearest_points", (PyCFunction)(void (*)(void))nearest_points, METH_FASTCALL,
     "nearest_points(queries, refs, index_out, dist_out): trees.nearest_python's indices "
     "and distances written (None), or NotImplemented (nothing written) for a value not "
     "finite."},
    {"close_pairs", (PyCFunction)(void (*)(void))close_pairs, METH_FASTCALL,
     "close_pairs(points, radius, out): trees.close_pairs_python's pairs written to out, "
     "their number returned, or NotImplemented (nothing written) for a point not finite."},
    {"setup", setup, METH_VARARGS,
     "setup(LabelledAssignment, max_listed_measurements, (DETECTED, OCCLUDED, DELETED), "
     "(MATCHED, NEW, FALSE_ALARM), listing_limit, listing_budget)"},
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
