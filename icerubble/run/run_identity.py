"""What makes a run's result: every input that determines it (issue 11).

A result file is named by scene, ridge, mu and tau_cr, which is what a user
looks for, but many more inputs change it: every other parameter, the mesh
(pile seed, element size, the pile's friction), the numerical options and the
engine's physics. The identity collects them; its hash, ``run_id``, is
recorded in the result, and a stored result is handed back only for a request
with the same id. A request that differs is refused with the differences
named, never answered with another run's result.
"""
import hashlib
import json
import math
import os
import socket

import numpy as np

from .. import parameters as P

# Bumped whenever a change of the engine alters what a run computes (forces,
# time step, settling, recording), so that results made before are not
# handed back as if the new code had made them. 5: the contact reach guard
# measures the nodes a split adds within one step(n) call from their
# reference places (it read past its origins before: runs with a finite
# contact_reach, the balanced and fast presets, and bond splits).
PHYSICS_VERSION = 5

# mesh attributes that describe the file, not the geometry: when, by which
# code and from which path it was written (the same mesh made in another
# folder, or by code that meshes alike, is the same mesh)
_VOLATILE_MESH_ATTRS = {"created", "code_version", "source_hash", "complete", "source", "source_pile"}


def mesh_digest(mesh):
    """sha256 of the mesh's arrays and its geometric attributes."""
    h = hashlib.sha256()
    for key in sorted(k for k in mesh if k != "attrs"):
        v = mesh[key]
        h.update(key.encode())
        if isinstance(v, np.ndarray):
            a = np.ascontiguousarray(v)
            h.update(str(a.dtype).encode() + str(a.shape).encode())
            h.update(a.tobytes())
        else:   # lists of per-block polygons and the like
            h.update(json.dumps(v, sort_keys=True, default=_json_default).encode())
    for k in sorted(mesh.get("attrs", {})):
        if k not in _VOLATILE_MESH_ATTRS:
            h.update(f"{k}={_plain(mesh['attrs'][k])!r}".encode())
    return h.hexdigest()


def _plain(v):
    """numpy scalars, arrays and bytes as plain Python values."""
    if isinstance(v, np.generic):
        return v.item()
    if isinstance(v, bytes):
        return v.decode()
    if isinstance(v, np.ndarray):
        return v.tolist()
    return v


def _json_default(v):
    p = _plain(v)
    return repr(v) if p is v else p


def identity(params, mesh, options):
    """The run's identity: validated request parameters (those the registry
    marks identity, icerubble/parameters.py), mesh digest, the numerical
    options that change the result, and the physics version.

    The geometry (keel_depth, domain_width, ...) is the mesh's, which the
    digest holds: it is not a parameter of the identity. Identities made
    before issue 27 held Table 1's geometry, which the run ignored: their
    run ids differ from today's for the same run (the stored result is then
    refused as another run's, its differences named: only those keys).
    """
    ident = {
        "physics_version": PHYSICS_VERSION,
        "parameters": {k: _plain(v) for k, v in sorted(params.items()) if P.REGISTRY[k].identity},
        "mesh_sha256": mesh_digest(mesh),
        "dt_fraction": _plain(getattr(options, "dt_fraction", None)),
        "mass_scaling_dt": _plain(getattr(options, "mass_scaling_dt", None)),
    }
    reach = getattr(options, "contact_reach", math.inf)
    if math.isfinite(reach):  # absent: the whole mesh
        ident["contact_reach"] = _plain(reach)
    settle = getattr(options, "settle_mass_scaling_dt", None)
    if settle is not None:  # absent: the settle ran at the loading's step
        ident["settle_mass_scaling_dt"] = _plain(settle)
    sleep = getattr(options, "sleep", None)
    if sleep is not None:  # absent: off (the identity of runs made before it existed)
        ident["sleep"] = {k: _plain(v) for k, v in sorted(sleep.items())}
    device = getattr(options, "device", "cpu")
    if device != "cpu":  # absent: the CPU engine; the GPU sums in another order (docs/gpu.md)
        ident["device"] = device
    return ident


def to_json(ident):
    """The identity as recorded in a result file (root attribute run_identity)."""
    return json.dumps(ident, sort_keys=True, default=_json_default)


def run_id(ident):
    return hashlib.sha256(to_json(ident).encode()).hexdigest()[:20]


def differences(stored, asked):
    """Human-readable list of what differs between two identities."""
    out = []
    for key in sorted(set(stored) | set(asked)):
        a, b = stored.get(key), asked.get(key)
        if key == "parameters":
            a, b = a or {}, b or {}
            for p in sorted(set(a) | set(b)):
                if a.get(p) != b.get(p):
                    out.append(f"{p}: stored {a.get(p)!r}, asked {b.get(p)!r}")
        elif a != b:
            out.append(f"{key}: stored {a!r}, asked {b!r}")
    return out


class RunLock:
    """``OUT.lock`` while a run is computed, so that a second request for the
    same result says so at once instead of computing it again and crashing at
    the write. A lock left by a process that no longer exists (same host) is
    taken over."""

    def __init__(self, out_path):
        self.path = out_path + ".lock"
        self.held = False

    def __enter__(self):
        me = f"{socket.gethostname()} {os.getpid()}"
        for _ in range(2):
            try:
                fd = os.open(self.path, os.O_CREAT | os.O_EXCL | os.O_WRONLY)
            except FileExistsError:
                try:
                    host, pid = open(self.path).read().split()
                except (OSError, ValueError):
                    host, pid = "", "0"
                if host == socket.gethostname() and not _alive(int(pid)):
                    os.remove(self.path)      # stale: its process is gone
                    continue
                raise RuntimeError(f"{self.path[:-5]} is being computed by process {pid} on {host or '?'} "
                                   f"(lock file {self.path}); wait for it, or delete the lock if that "
                                   f"process is gone") from None
            with os.fdopen(fd, "w") as f:
                f.write(me)
            self.held = True
            return self
        raise RuntimeError(f"could not take the lock {self.path}")

    def __exit__(self, *exc):
        if self.held:
            try:
                os.remove(self.path)
            except FileNotFoundError:
                pass
            self.held = False
        return False


def _alive(pid):
    if pid <= 0:
        return False
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True
