#!/usr/bin/env python3
"""Integrate one material point of a pnc card from Python through the plugin's C ABI
(ctypes only, no compiled glue). Run:

    python3 integrate_point.py --card card.h5 [--plugin /path/libpnc_material.so.1]

(the plugin defaults to $PNC_MATERIAL_PLUGIN). It reads the card's constants through the
C ABI metadata (pnc_material_constant_name / pnc_material_constant), builds the undamaged
stiffness C0 from them (docs/theory.md §1.1: normal block C11..C23, shear diagonal
C44 C55 C66; the pp model reads it isotropically), checks that an elastic increment gives
sigma = C0 eps and that the tangent is C0, then loads the point into damage. Units SI:
strain dimensionless with engineering shear, stress Pa; Voigt order 11,22,33,23,13,12.
Exit status 0 when every check holds, 1 otherwise. Tested by ctest (material_cli.python_ctypes).
"""
import argparse
import ctypes as C
import os
import sys

import numpy as np

OK = 0


def load(plugin):
    lib = C.CDLL(plugin)
    dp = C.POINTER(C.c_double)
    lib.pnc_material_abi_version.restype = C.c_int
    lib.pnc_material_create.restype = C.c_void_p
    lib.pnc_material_create.argtypes = [C.c_char_p, C.c_char_p, C.c_size_t]
    lib.pnc_material_destroy.argtypes = [C.c_void_p]
    lib.pnc_material_model.restype = C.c_char_p
    lib.pnc_material_model.argtypes = [C.c_void_p]
    for f in ("pnc_material_n_constants", "pnc_material_n_state"):
        getattr(lib, f).restype = C.c_int
        getattr(lib, f).argtypes = [C.c_void_p]
    lib.pnc_material_constant_name.restype = C.c_char_p
    lib.pnc_material_constant_name.argtypes = [C.c_void_p, C.c_int]
    lib.pnc_material_constant.restype = C.c_double
    lib.pnc_material_constant.argtypes = [C.c_void_p, C.c_int]
    lib.pnc_material_state_name.restype = C.c_char_p
    lib.pnc_material_state_name.argtypes = [C.c_void_p, C.c_int]
    lib.pnc_material_rotation.argtypes = [C.c_void_p, dp]
    lib.pnc_material_init_state.argtypes = [C.c_void_p, dp]
    lib.pnc_material_integrate.restype = C.c_int
    lib.pnc_material_integrate.argtypes = [C.c_void_p, dp, dp, dp, dp, dp, dp, C.c_char_p,
                                           C.c_size_t]
    return lib


def ptr(a):
    return a.ctypes.data_as(C.POINTER(C.c_double))


def c0_from_constants(model, k):
    """The undamaged stiffness of docs/theory.md §1.1 (engineering Voigt)."""
    C0 = np.zeros((6, 6))
    if model == "pnc":
        C0[0, 0], C0[1, 1], C0[2, 2] = k["C11"], k["C22"], k["C33"]
        C0[0, 1] = C0[1, 0] = k["C12"]
        C0[0, 2] = C0[2, 0] = k["C13"]
        C0[1, 2] = C0[2, 1] = k["C23"]
        C0[3, 3], C0[4, 4], C0[5, 5] = k["C44"], k["C55"], k["C66"]
    else:  # pp: C22 = C33 = C11, C13 = C23 = C12, C55 = C66 = C44
        for i in range(3):
            for j in range(3):
                C0[i, j] = k["C11"] if i == j else k["C12"]
            C0[3 + i, 3 + i] = k["C44"]
    return C0


def voigt_rotation(R):
    """T with eps_local = T eps_global (engineering shear), from e_local = R e R^T."""
    T = np.zeros((6, 6))
    for j in range(6):
        e = np.zeros(6)
        e[j] = 1.0
        t = np.array([[e[0], e[5] / 2, e[4] / 2], [e[5] / 2, e[1], e[3] / 2],
                      [e[4] / 2, e[3] / 2, e[2]]])
        tl = R @ t @ R.T
        T[:, j] = [tl[0, 0], tl[1, 1], tl[2, 2], 2 * tl[1, 2], 2 * tl[0, 2], 2 * tl[0, 1]]
    return T


def check(cond, what):
    global OK
    print(("ok     " if cond else "FAILED ") + what)
    if not cond:
        OK = 1


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--card", required=True)
    ap.add_argument("--plugin", default=os.environ.get("PNC_MATERIAL_PLUGIN", ""))
    a = ap.parse_args()
    if not a.plugin:
        sys.exit("integrate_point.py: field '--plugin': value '': give the plugin path or set "
                 "PNC_MATERIAL_PLUGIN")
    lib = load(a.plugin)
    check(lib.pnc_material_abi_version() == 1, "ABI version 1")
    err = C.create_string_buffer(1024)
    m = lib.pnc_material_create(a.card.encode(), err, len(err))
    if not m:
        sys.exit("integrate_point.py: " + err.value.decode())
    model = lib.pnc_material_model(m).decode()
    k = {lib.pnc_material_constant_name(m, i).decode(): lib.pnc_material_constant(m, i)
         for i in range(lib.pnc_material_n_constants(m))}
    ns = lib.pnc_material_n_state(m)
    states = [lib.pnc_material_state_name(m, i).decode() for i in range(ns)]
    R = np.zeros(9)
    lib.pnc_material_rotation(m, ptr(R))
    R = R.reshape(3, 3)
    T = voigt_rotation(R)
    C0 = T.T @ c0_from_constants(model, k) @ T  # global frame: sigma = T^T C0 T eps
    print("card %s: model %s, %d constants, state %s" % (a.card, model, len(k), " ".join(states)))

    s0, s1 = np.zeros(ns), np.zeros(ns)
    lib.pnc_material_init_state(m, ptr(s0))
    eps0 = np.zeros(6)
    deps = np.array([1e-3, -2e-4, 3e-4, 4e-4, -1e-4, 5e-4])  # well below the damage onset
    sig, K = np.zeros(6), np.zeros(36)
    st = lib.pnc_material_integrate(m, ptr(s0), ptr(s1), ptr(eps0), ptr(deps), ptr(sig), ptr(K),
                                    err, len(err))
    check(st == 0, "elastic increment accepted")
    ref = C0 @ deps
    check(np.max(np.abs(sig - ref)) <= 1e-12 * np.max(np.abs(ref)),
          "elastic stress = C0 eps (max |diff| %.3g Pa of %.3g Pa)"
          % (np.max(np.abs(sig - ref)), np.max(np.abs(ref))))
    check(np.max(np.abs(K.reshape(6, 6) - C0)) <= 1e-12 * np.max(np.abs(C0)),
          "elastic tangent = C0")

    # uniaxial strain into damage: the damage variable grows, the secant stiffness drops
    s0[:] = s1
    eps0 = deps.copy()
    step = np.array([0.01, 0, 0, 0, 0, 0])
    for _ in range(15):
        st = lib.pnc_material_integrate(m, ptr(s0), ptr(s1), ptr(eps0), ptr(step), ptr(sig),
                                        ptr(K), err, len(err))
        if st != 0:
            check(False, "damaging increment: " + err.value.decode())
            break
        s0[:] = s1
        eps0 += step
    d = s0[ns // 2]
    check(d > 0, "damaged at eps11 = %.3f: %s = %.4f" % (eps0[0], states[ns // 2], d))
    check(sig[0] < (C0 @ eps0)[0], "damaged stress below the undamaged C0 eps")
    lib.pnc_material_destroy(C.c_void_p(m))
    return OK


if __name__ == "__main__":
    sys.exit(main())
