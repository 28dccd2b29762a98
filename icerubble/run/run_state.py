"""A punch-through run's progress (issue 27, item 2): the phase and the
record of the settle and of the loading so far, in one object.

Beside the engine's state and the recorder's rows, this is what a checkpoint
saves of the driver (run/checkpoint.py writes ``to_attrs()`` as /driver's
attributes and reads them back with ``restore``); the driver's other members
are made from the run's inputs again. None is stored as NaN.
"""
import json
import math
from dataclasses import dataclass, field, fields


@dataclass
class RunState:
    phase: str = "settle"                  # "settle", then "load"
    t_settle: float = None                 # model time when settling started [s]
    t_load: float = None                   # model time when loading started [s]
    y_top0: float = None                   # indenter top at rest [m]
    F_at_rest: float = math.nan            # force that holds the indenter at rest [N/m]
    settle_time: float = math.nan          # simulated time the settle took [s]
    settle_max_speed: float = math.nan     # largest node speed at rest [m/s]
    settle_max_block_move: float = math.nan  # largest block (node centroid) move while settling [m]
    settle_splits: int = 0                 # bond points split while settling (settle_bonds='checked')
    load_steps: int = 0                    # steps of the load phase ...
    load_element_steps: int = 0            # ... and the triangles they computed (sleeping far field)
    # wall time of each phase summed over the processes that ran it, so that a
    # resumed run reports what it cost, not what its last process did (time
    # after the last checkpoint of a stopped process is redone, so not counted);
    # a run loading from a shared rest state reports the settle that made it
    wall_settle_s: float = 0.0
    wall_load_s: float = 0.0
    vtu_entries: list = field(default_factory=list)   # (y_I, file) of the VTU pieces written

    def to_attrs(self):
        """{name: value} for a checkpoint's /driver attributes."""
        out = {k: (math.nan if getattr(self, k) is None else getattr(self, k)) for k in _SCALARS}
        out["vtu_entries"] = json.dumps(self.vtu_entries)
        return out

    def restore(self, attrs):
        """Take the fields a checkpoint's /driver attributes hold (those written
        before a field existed keep its default)."""
        for k in _SCALARS:
            if k not in attrs:
                continue
            v = attrs[k]
            if isinstance(v, bytes):
                v = v.decode()
            setattr(self, k, v.item() if hasattr(v, "item") else v)
        self.vtu_entries = [tuple(e) for e in json.loads(attrs["vtu_entries"])]


# the fields stored as /driver attributes one by one (vtu_entries as JSON)
_SCALARS = tuple(f.name for f in fields(RunState) if f.name != "vtu_entries")
