/* One-state kernel as a CPython extension: a generated kernel (kernel.c, which defines
 * linkage_prepare, linkage_one and LINKAGE_N_*) behind one fast-call function.
 *
 * bind(state) returns a builtin function of the LINKAGE_N_X inputs bound to `state`, a
 * bytes object: the LINKAGE_N_Q doubles of the parameter step, then one byte per output,
 * nonzero where the output must be finite. The function returns the outputs as a tuple of
 * floats where it takes the state; None for an input that is not a finite float (the
 * caller checks and converts); the code of the failed guard (an int >= 1); or 0 where an
 * output that must be finite is not. The caller then classifies the state.
 *
 * bind(state, cls, slots, values) returns the same function, except that where it takes
 * the state it returns an instance of the class `cls` made without calling its __init__:
 * the slot named slots[0] holds the outputs, unboxed (a read-only sequence of floats,
 * copied and pickled as a tuple), the one named slots[k] values[k - 1] (slots: member
 * descriptors of cls, as __slots__ makes them). Compiled with MODULE_INIT
 * defined as the PyInit_ name of the module. */
#define PY_SSIZE_T_CLEAN
#include <Python.h>
#include <string.h>

#include "kernel.c"

#define STATE_SIZE (LINKAGE_N_Q * sizeof(double) + LINKAGE_N_Y)

/* The kernel at the inputs `args`: 1 with the outputs in y, or 0 with *answer what to
 * return instead (None, a guard's code, or NULL with an exception set). */
static int run(PyObject *state, PyObject *const *args, Py_ssize_t nargs, double *y,
               PyObject **answer) {
    double q[LINKAGE_N_Q + 1], x[LINKAGE_N_X + 1];
    const char *bytes = PyBytes_AS_STRING(state);
    if (nargs != LINKAGE_N_X) {
        PyErr_Format(PyExc_TypeError, "the kernel takes %d inputs, got %zd",
                     LINKAGE_N_X, nargs);
        *answer = NULL;
        return 0;
    }
    for (Py_ssize_t k = 0; k < nargs; k++) {
        if (!PyFloat_CheckExact(args[k]) || !isfinite(x[k] = PyFloat_AS_DOUBLE(args[k]))) {
            *answer = Py_NewRef(Py_None);
            return 0;
        }
    }
    memcpy(q, bytes, LINKAGE_N_Q * sizeof(double));
    const int code = linkage_one(q, x, y);
    if (code) {
        *answer = PyLong_FromLong(code);
        return 0;
    }
    const char *checked = bytes + LINKAGE_N_Q * sizeof(double);
    for (int k = 0; k < LINKAGE_N_Y; k++)
        if (checked[k] && !isfinite(y[k])) {
            *answer = PyLong_FromLong(0);
            return 0;
        }
    return 1;
}

static PyObject *outputs(PyObject *state, PyObject *const *args, Py_ssize_t nargs) {
    double y[LINKAGE_N_Y + 1];
    PyObject *answer;
    if (!run(state, args, nargs, y, &answer)) return answer;
    PyObject *out = PyTuple_New(LINKAGE_N_Y);
    if (out == NULL) return NULL;
    for (int k = 0; k < LINKAGE_N_Y; k++) {
        PyObject *v = PyFloat_FromDouble(y[k]);
        if (v == NULL) {
            Py_DECREF(out);
            return NULL;
        }
        PyTuple_SET_ITEM(out, k, v);
    }
    /* floats only: no cycle can pass through it (the collector would untrack it too,
     * after traversing it in each collection until then) */
    PyObject_GC_UnTrack(out);
    return out;
}

/* The outputs of a state held unboxed: a read-only sequence of floats (each made when
 * read), one allocation where a tuple takes one per output. */
typedef struct {
    PyObject_VAR_HEAD
    double v[1];
} Doubles;

static Py_ssize_t doubles_length(PyObject *o) { return Py_SIZE(o); }

static PyObject *doubles_item(PyObject *o, Py_ssize_t i) {
    if (i < 0 || i >= Py_SIZE(o)) {
        PyErr_SetString(PyExc_IndexError, "index out of range");
        return NULL;
    }
    return PyFloat_FromDouble(((Doubles *)o)->v[i]);
}

static PyObject *doubles_tuple(PyObject *o) {
    PyObject *out = PyTuple_New(Py_SIZE(o));
    for (Py_ssize_t k = 0; out != NULL && k < Py_SIZE(o); k++) {
        PyObject *v = PyFloat_FromDouble(((Doubles *)o)->v[k]);
        if (v == NULL) Py_CLEAR(out);
        else PyTuple_SET_ITEM(out, k, v);
    }
    return out;
}

/* copied and pickled as the tuple of its floats */
static PyObject *doubles_reduce(PyObject *o, PyObject *unused) {
    (void)unused;
    PyObject *values = doubles_tuple(o);
    return values == NULL ? NULL : Py_BuildValue("(O(N))", (PyObject *)&PyTuple_Type, values);
}

static PyObject *doubles_repr(PyObject *o) {
    PyObject *values = doubles_tuple(o);
    if (values == NULL) return NULL;
    PyObject *text = PyObject_Repr(values);
    Py_DECREF(values);
    return text;
}

static PySequenceMethods doubles_sequence = {.sq_length = doubles_length,
                                             .sq_item = doubles_item};
static PyMethodDef doubles_methods[] = {
    {"__reduce__", doubles_reduce, METH_NOARGS, "the tuple of its floats"},
    {NULL, NULL, 0, NULL},
};
static PyTypeObject DoublesType = {
    PyVarObject_HEAD_INIT(NULL, 0).tp_name = "kernel.doubles",
    .tp_basicsize = offsetof(Doubles, v),
    .tp_itemsize = sizeof(double),
    .tp_flags = Py_TPFLAGS_DEFAULT,
    .tp_doc = "a state's outputs, unboxed: a read-only sequence of floats",
    .tp_as_sequence = &doubles_sequence,
    .tp_methods = doubles_methods,
    .tp_repr = doubles_repr,
};

static PyMethodDef one_def = {"kernel", (PyCFunction)(void (*)(void))outputs, METH_FASTCALL,
                              "kernel(*inputs): the outputs as a tuple, None, or a code"};

/* bound: (state, cls, descriptor 0, ..., descriptor n, value 1, ..., value n) */
static PyObject *instance(PyObject *bound, PyObject *const *args, Py_ssize_t nargs) {
    double y[LINKAGE_N_Y + 1];
    PyObject *answer;
    if (!run(PyTuple_GET_ITEM(bound, 0), args, nargs, y, &answer)) return answer;
    Doubles *out = PyObject_NewVar(Doubles, &DoublesType, LINKAGE_N_Y);
    if (out == NULL) return NULL;
    memcpy(out->v, y, LINKAGE_N_Y * sizeof(double));
    PyTypeObject *cls = (PyTypeObject *)PyTuple_GET_ITEM(bound, 1);
    const Py_ssize_t n = (PyTuple_GET_SIZE(bound) - 1) / 2;
    PyObject *obj = cls->tp_alloc(cls, 0);
    if (obj == NULL) {
        Py_DECREF(out);
        return NULL;
    }
    for (Py_ssize_t k = 0; k < n; k++) {
        PyObject *d = PyTuple_GET_ITEM(bound, 2 + k);
        PyObject *v = k == 0 ? (PyObject *)out : PyTuple_GET_ITEM(bound, 1 + n + k);
        if (Py_TYPE(d)->tp_descr_set(d, obj, v) < 0) {
            Py_DECREF(out);
            Py_DECREF(obj);
            return NULL;
        }
    }
    Py_DECREF(out);
    return obj;
}

static PyMethodDef instance_def = {
    "kernel", (PyCFunction)(void (*)(void))instance, METH_FASTCALL,
    "kernel(*inputs): the outputs in an instance of the bound class, None, or a code"};

static PyObject *bind(PyObject *module, PyObject *args) {
    (void)module;
    PyObject *state, *cls = NULL, *slots = NULL, *values = NULL;
    if (!PyArg_ParseTuple(args, "O|OO!O!:bind", &state, &cls, &PyTuple_Type, &slots,
                          &PyTuple_Type, &values))
        return NULL;
    if (!PyBytes_CheckExact(state) || PyBytes_GET_SIZE(state) != (Py_ssize_t)STATE_SIZE) {
        PyErr_Format(PyExc_ValueError, "bind() takes bytes of length %zu",
                     (size_t)STATE_SIZE);
        return NULL;
    }
    if (cls == NULL) return PyCFunction_New(&one_def, state);
    if (slots == NULL || values == NULL || !PyType_Check(cls) ||
        PyTuple_GET_SIZE(slots) != PyTuple_GET_SIZE(values) + 1) {
        PyErr_SetString(PyExc_TypeError,
                        "bind(state, cls, slots, values): a class, a tuple of its slots' "
                        "names and a tuple of one value less");
        return NULL;
    }
    const Py_ssize_t n = PyTuple_GET_SIZE(slots);
    PyObject *bound = PyTuple_New(2 + 2 * n - 1);
    if (bound == NULL) return NULL;
    Py_INCREF(state);
    PyTuple_SET_ITEM(bound, 0, state);
    Py_INCREF(cls);
    PyTuple_SET_ITEM(bound, 1, cls);
    for (Py_ssize_t k = 0; k < n; k++) {
        PyObject *d = PyObject_GetAttr(cls, PyTuple_GET_ITEM(slots, k));
        if (d == NULL) {
            Py_DECREF(bound);
            return NULL;
        }
        if (!Py_IS_TYPE(d, &PyMemberDescr_Type)) {
            PyErr_Format(PyExc_TypeError, "%R is not a slot of %R",
                         PyTuple_GET_ITEM(slots, k), cls);
            Py_DECREF(d);
            Py_DECREF(bound);
            return NULL;
        }
        PyTuple_SET_ITEM(bound, 2 + k, d);
    }
    for (Py_ssize_t k = 1; k < n; k++) {
        PyObject *v = PyTuple_GET_ITEM(values, k - 1);
        Py_INCREF(v);
        PyTuple_SET_ITEM(bound, 1 + n + k, v);
    }
    PyObject *fn = PyCFunction_New(&instance_def, bound);
    Py_DECREF(bound);
    return fn;
}

static PyMethodDef methods[] = {
    {"bind", bind, METH_VARARGS,
     "bind(state[, cls, slots, values]): the kernel with its parameter step's values"},
    {NULL, NULL, 0, NULL},
};

static struct PyModuleDef module_def = {PyModuleDef_HEAD_INIT, "kernel", NULL, -1, methods,
                                        NULL, NULL, NULL, NULL};

PyMODINIT_FUNC MODULE_INIT(void) {
    if (PyType_Ready(&DoublesType) < 0) return NULL;
    PyObject *m = PyModule_Create(&module_def);
    if (m != NULL && (PyModule_AddIntConstant(m, "n_inputs", LINKAGE_N_X) < 0 ||
                      PyModule_AddIntConstant(m, "n_outputs", LINKAGE_N_Y) < 0 ||
                      PyModule_AddIntConstant(m, "n_frozen", LINKAGE_N_Q) < 0)) {
        Py_DECREF(m);
        return NULL;
    }
    return m;
}
