"""The native part (python/rotleap/native.c, built as _rotleap_native.so) loaded with ctypes.

ctypes releases the GIL for every call into the library, and takes it again for the Python
reporters the library calls back.  ROTLEAP_NATIVE (a path) overrides the module next to this
file: CTest uses it to test the build tree's module."""
import ctypes
import os

_dbl_p = ctypes.POINTER(ctypes.c_double)
CALLBACK = ctypes.CFUNCTYPE(ctypes.c_int, ctypes.c_int)
# the external force: f, k, virial, energy, forces_only
FORCE_CALLBACK = ctypes.CFUNCTYPE(ctypes.c_int, _dbl_p, _dbl_p, _dbl_p, _dbl_p, ctypes.c_int)

INTERRUPTED = -2       # rlpy_run: SIGINT between two steps
# the streams a checkpoint marks (app/outputs.h OUT_*): rlpy_stream
THERMO, TRAJ, TOPOLOGY, SAMPLES, NSTREAMS = range(5)
REPORTER_RAISED = -3   # rlpy_run: a Python reporter raised


def _load():
    path = os.environ.get("ROTLEAP_NATIVE") or os.path.join(os.path.dirname(__file__), "_rotleap_native.so")
    lib = ctypes.CDLL(path)
    P = ctypes.c_void_p
    sigs = {
        "rlpy_error": (ctypes.c_char_p, []),
        "rlpy_version": (ctypes.c_char_p, []),
        "rlpy_open": (P, [ctypes.c_char_p, ctypes.POINTER(ctypes.c_char_p), ctypes.c_int]),
        "rlpy_close": (None, [P]),
        "rlpy_count": (ctypes.c_int, [P]),
        "rlpy_nrot": (ctypes.c_int, [P]),
        "rlpy_step": (ctypes.c_long, [P]),
        "rlpy_time": (ctypes.c_double, [P]),
        "rlpy_timestep": (ctypes.c_double, [P]),
        "rlpy_deck_steps": (ctypes.c_long, [P]),
        "rlpy_energy_every": (ctypes.c_long, [P]),
        "rlpy_thermo_every": (ctypes.c_long, [P]),
        "rlpy_trajectory_every": (ctypes.c_long, [P]),
        "rlpy_checkpoint_every": (ctypes.c_long, [P]),
        "rlpy_site_trajectory": (ctypes.c_int, [P]),
        "rlpy_checkpoint": (ctypes.c_int, [P, ctypes.c_char_p, ctypes.POINTER(ctypes.c_long)]),
        "rlpy_stream": (ctypes.c_int, [P, ctypes.c_int, ctypes.c_char_p, ctypes.c_long]),
        "rlpy_journal_open": (ctypes.c_int, [P, ctypes.c_char_p]),
        "rlpy_journal_close": (ctypes.c_int, [P]),
        "rlpy_add_external": (ctypes.c_int, [P, FORCE_CALLBACK]),
        "rlpy_scan": (ctypes.c_int, [ctypes.c_int, ctypes.POINTER(ctypes.c_char_p)]),
        "rlpy_traj_open": (P, [P, ctypes.c_char_p, ctypes.c_int, ctypes.c_long, ctypes.c_char_p]),
        "rlpy_traj_frame": (ctypes.c_int, [P, P]),
        "rlpy_traj_close": (ctypes.c_int, [P]),
        "rlpy_traj_skip": (ctypes.c_long, [P]),
        "rlpy_real_units": (ctypes.c_int, [P]),
        "rlpy_model": (ctypes.c_char_p, [P]),
        "rlpy_note": (ctypes.c_char_p, [P]),
        "rlpy_fallbacks": (ctypes.c_long, [P]),
        "rlpy_kind": (ctypes.c_int, [P]),
        "rlpy_nenergies": (ctypes.c_int, [P]),
        "rlpy_energy_name": (ctypes.c_char_p, [P, ctypes.c_int]),
        "rlpy_box": (None, [P, _dbl_p]),
        "rlpy_nvalues": (ctypes.c_int, []),
        "rlpy_report": (ctypes.c_int, [P, _dbl_p]),
        "rlpy_report_forces": (ctypes.c_int, [P, _dbl_p, _dbl_p]),
        "rlpy_observe": (ctypes.c_int, [P, _dbl_p]),
        "rlpy_run": (ctypes.c_int, [P, ctypes.c_long, ctypes.c_int, ctypes.POINTER(ctypes.c_int),
                                    ctypes.POINTER(ctypes.c_long), CALLBACK, ctypes.c_int, ctypes.c_int,
                                    ctypes.POINTER(ctypes.c_long)]),
        "rlpy_get": (ctypes.c_int, [P, ctypes.c_int, _dbl_p]),
        "rlpy_set": (ctypes.c_int, [P, ctypes.c_int, _dbl_p]),
        "rlpy_catalog_count": (ctypes.c_int, []),
        "rlpy_catalog_text": (ctypes.c_char_p, [ctypes.c_int, ctypes.c_int]),
        "rlpy_catalog_params": (ctypes.c_int, [ctypes.c_int, _dbl_p]),
        "rlpy_catalog_molecule": (ctypes.c_int, [ctypes.c_int, _dbl_p, _dbl_p, ctypes.c_char_p] + [_dbl_p] * 7),
        "rlpy_molecule": (ctypes.c_int, [P, _dbl_p, _dbl_p, ctypes.c_char_p] + [_dbl_p] * 7),
        "rlpy_interactions": (None, [P, _dbl_p]),
        "rlpy_thermo_header": (ctypes.c_char_p, [P]),
        "rlpy_thermo_row": (ctypes.c_char_p, [P]),
    }
    for name, (res, args) in sigs.items():
        f = getattr(lib, name)
        f.restype = res
        f.argtypes = args
    return lib


lib = _load()


def error_text():
    return lib.rlpy_error().decode("utf-8", "replace")


def dptr(a):
    """A double* to the data of the C-contiguous float64 array a."""
    return a.ctypes.data_as(_dbl_p)
