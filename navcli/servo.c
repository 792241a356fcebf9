/* The wheels' velocity servo of navcli.world, in C: the same three Chipmunk calls as the Python
 * servo (World._drive), made inside Chipmunk's step without calling back into Python.
 *
 * Built with the compiled build (setup.py) and imported by navcli/world.py alone, which hands this
 * module Chipmunk's functions as addresses taken from pymunk's cffi library (the very functions
 * pymunk's Body and Space call), and hands Chipmunk this module's velocity function through the same
 * library (cpBodySetVelocityUpdateFunc). So nothing here links against pymunk or needs Chipmunk's
 * headers, and no code is made at run time (no writable and executable memory, as a cffi callback
 * closure would need).
 *
 * The set point (the speed and turn rate the wheels execute this physics step) cannot ride on the
 * body (pymunk holds its user data): step() puts it where the velocity function finds it for the
 * length of one Chipmunk step, per thread (pymunk's collision callbacks run Python, which may let
 * another thread step another world meanwhile), and puts back what was there before.
 */

#define PY_SSIZE_T_CLEAN
#include <Python.h>
#include <math.h>

#if defined(_MSC_VER)
#define THREAD_LOCAL __declspec(thread)
#else
#define THREAD_LOCAL _Thread_local
#endif

/* Chipmunk's cpVect with cpFloat a double: world.py checks that pymunk's library declares these types */
typedef struct {
    double x, y;
} Vect;

typedef double (*GetAngle)(void *body);
typedef void (*SetVelocity)(void *body, Vect v);
typedef void (*SetAngularVelocity)(void *body, double w);
typedef void (*SpaceStep)(void *space, double dt);

static GetAngle get_angle;
static SetVelocity set_velocity;
static SetAngularVelocity set_angular_velocity;
static SpaceStep space_step;

typedef struct {
    void *body; /* the body it is for: any other body the space holds is left alone */
    double v;   /* m/s along the heading */
    double w;   /* rad/s */
} SetPoint;

static THREAD_LOCAL const SetPoint *current;

/* Chipmunk's cpBodyVelocityFunc. Outside step() (no set point) it leaves the velocity as it is. */
static void velocity(void *body, Vect gravity, double damping, double dt) {
    const SetPoint *s = current;
    (void)gravity, (void)damping, (void)dt;
    if (s == NULL || s->body != body)
        return;
    double a = get_angle(body);
    Vect v = {s->v * cos(a), s->v * sin(a)};
    set_velocity(body, v);
    set_angular_velocity(body, s->w);
}

static int address(PyObject *o, void **out) {
    *out = PyLong_AsVoidPtr(o);
    if (*out == NULL && !PyErr_Occurred())
        PyErr_SetString(PyExc_ValueError, "a null address");
    return *out == NULL ? -1 : 0;
}

static PyObject *bind(PyObject *self, PyObject *const *args, Py_ssize_t n) {
    void *f[4];
    (void)self;
    if (n != 4) {
        PyErr_SetString(PyExc_TypeError,
                        "bind(get_angle, set_velocity, set_angular_velocity, space_step): four addresses");
        return NULL;
    }
    for (int i = 0; i < 4; i++)
        if (address(args[i], &f[i]) < 0)
            return NULL;
    get_angle = (GetAngle)f[0];
    set_velocity = (SetVelocity)f[1];
    set_angular_velocity = (SetAngularVelocity)f[2];
    space_step = (SpaceStep)f[3];
    return PyLong_FromVoidPtr((void *)velocity);
}

static PyObject *step(PyObject *self, PyObject *const *args, Py_ssize_t n) {
    SetPoint s;
    void *space;
    double dt;
    (void)self;
    if (n != 5) {
        PyErr_SetString(PyExc_TypeError, "step(space, body, v, w, dt): five arguments");
        return NULL;
    }
    if (space_step == NULL) {
        PyErr_SetString(PyExc_RuntimeError, "step() before bind()");
        return NULL;
    }
    if (address(args[0], &space) < 0 || address(args[1], &s.body) < 0)
        return NULL;
    s.v = PyFloat_AsDouble(args[2]);
    s.w = PyFloat_AsDouble(args[3]);
    dt = PyFloat_AsDouble(args[4]);
    if (PyErr_Occurred())
        return NULL;
    const SetPoint *outer = current;
    current = &s;
    space_step(space, dt);
    current = outer;
    Py_RETURN_NONE;
}

static PyMethodDef methods[] = {
    {"bind", (PyCFunction)(void (*)(void))bind, METH_FASTCALL,
     "bind(get_angle, set_velocity, set_angular_velocity, space_step) -> int\n\n"
     "Take Chipmunk's cpBodyGetAngle, cpBodySetVelocity, cpBodySetAngularVelocity and cpSpaceStep\n"
     "(their addresses); return the address of the velocity function (a cpBodyVelocityFunc)."},
    {"step", (PyCFunction)(void (*)(void))step, METH_FASTCALL,
     "step(space, body, v, w, dt)\n\n"
     "One cpSpaceStep of dt seconds, in which the velocity function drives ``body`` at v m/s along\n"
     "its heading and w rad/s (addresses of the cpSpace and the cpBody)."},
    {NULL, NULL, 0, NULL},
};

static struct PyModuleDef module = {
    PyModuleDef_HEAD_INIT, "navcli.servo", "The wheels' velocity servo of navcli.world, in C.", -1, methods,
};

PyMODINIT_FUNC PyInit_servo(void) { return PyModule_Create(&module); }
