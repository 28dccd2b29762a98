"""Matplotlib set-up shared by the figures: Agg backend, one look, PNG + PDF output."""
import os

import matplotlib

from icerubble.files.output_path import whole_file

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

MU_STYLE = {0.05: dict(color="tab:blue", marker="o", mfc="white"),
            0.3: dict(color="tab:red", marker="o", mfc="tab:red")}

plt.rcParams.update({"figure.dpi": 110, "savefig.dpi": 150, "font.size": 9,
                     "axes.grid": True, "grid.alpha": 0.3, "legend.fontsize": 8})


def mu_style(mu):
    """Marker style per friction coefficient: open markers mu = 0.05, filled mu = 0.3
    (the paper's Fig. 10 marker fill)."""
    for k, v in MU_STYLE.items():
        if abs(mu - k) < 1e-9:
            return dict(v)
    return dict(color="tab:green", marker="s", mfc="tab:green")


def new(ncols=1, nrows=1, width=6.0, height=3.6, **kw):
    return plt.subplots(nrows, ncols, figsize=(width, height), squeeze=False, **kw)


def save(fig, out_dir, stem, caption):
    """Write ``stem``.png and ``stem``.pdf into ``out_dir``; returns the two paths.
    ``caption`` goes into the figure's suptitle so a lone PNG says what it is."""
    fig.suptitle(caption, fontsize=9)
    fig.tight_layout()
    paths = []
    for ext in ("png", "pdf"):
        p = os.path.join(out_dir, f"{stem}.{ext}")
        with whole_file(p, "wb") as fh:   # a full disk leaves no figure that looks whole
            fig.savefig(fh, format=ext)
        paths.append(p)
    plt.close(fig)
    return paths


def discard_open():
    """Close every figure still open: one whose drawing stopped before ``save``
    (a run without the snapshots it needs) would otherwise stay in pyplot's registry."""
    plt.close("all")
