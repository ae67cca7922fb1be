/* Buffer helpers shared by the C extensions (detection/_cfeatures.c, tracking/_ckalman.c,
 * tracking/mht/_clisting.c's detection costs and node making):
 * numpy arrays (or any object with the buffer protocol) taken as C-contiguous doubles,
 * 64-bit integers or bools, and released. setup.py compiles the checksum of each source
 * followed by this header into its extension (extensions.source_hash), so a changed header
 * makes every extension that includes it stale. C99, the CPython C API only. */
#ifndef LP_CBUFFERS_H
#define LP_CBUFFERS_H

#define PY_SSIZE_T_CLEAN
#include <Python.h>

#include <string.h>

typedef struct {
    Py_buffer view;
    int held;
} Buf;

/* A C-contiguous buffer of `count` items of 8 bytes, doubles ('d') or 64-bit integers
 * ('q' or 'l'); sets ValueError and returns -1 otherwise. */
static int take(PyObject *obj, Buf *b, int integer, int writable, Py_ssize_t count,
                const char *name) {
    int flags = PyBUF_C_CONTIGUOUS | PyBUF_FORMAT | (writable ? PyBUF_WRITABLE : 0);
    if (PyObject_GetBuffer(obj, &b->view, flags) < 0) return -1;
    b->held = 1;
    const char *f = b->view.format ? b->view.format : "B";
    if (*f == '<' || *f == '=' || *f == '@') f++;
    int ok = b->view.itemsize == 8 &&
             (integer ? (strcmp(f, "q") == 0 || strcmp(f, "l") == 0) : strcmp(f, "d") == 0) &&
             (count < 0 || b->view.len == count * 8);
    if (!ok) {
        PyErr_Format(PyExc_ValueError, "%s: expected %zd %s", name, count,
                     integer ? "int64" : "float64");
        return -1;
    }
    return 0;
}

/* A C-contiguous buffer of `count` bools ('?'); sets ValueError and returns -1 otherwise. */
static int take_bools(PyObject *obj, Buf *b, Py_ssize_t count, const char *name) {
    if (PyObject_GetBuffer(obj, &b->view, PyBUF_C_CONTIGUOUS | PyBUF_FORMAT) < 0) return -1;
    b->held = 1;
    if (b->view.itemsize != 1 || !b->view.format || strcmp(b->view.format, "?") != 0 ||
        b->view.len != count) {
        PyErr_Format(PyExc_ValueError, "%s: expected %zd bool", name, count);
        return -1;
    }
    return 0;
}

static void release(Buf *bufs, int n) {
    for (int i = 0; i < n; i++)
        if (bufs[i].held) PyBuffer_Release(&bufs[i].view);
}

#endif /* LP_CBUFFERS_H */
