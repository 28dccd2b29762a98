"""Damaged copies of HDF5 input files, for the tests that check they are refused."""
import os
import shutil

import h5py


def broken(src, dst_dir, edit, name=None):
    """A copy of src in dst_dir (as `name`, default src's name) with edit(h5py.File) applied."""
    dst = os.path.join(str(dst_dir), name or os.path.basename(str(src)))
    shutil.copy(src, dst)
    with h5py.File(dst, "r+") as f:
        edit(f)
    return dst


def replace(name, data, units=None):
    """An edit that replaces dataset `name` by `data`, keeping its units (or setting `units`)."""
    def edit(f):
        old_units = f[name].attrs.get("units")
        del f[name]
        d = f.create_dataset(name, data=data)
        u = old_units if units is None else units
        if u is not None:
            d.attrs["units"] = u
    return edit
