"""postproc: analyses and figures of Polojärvi & Tuhkuri (2013) from run results.

Modules (one purpose each):
  results         icerubble/files/results.py (read one run result -> RunResult) under its former name
  loads           F^m (the cohesive peak), record maximum, mean load over an interval
  failure_plane   failed (split or fully failed) bond points, angle alpha (Figs. 12, 13)
  plug            plug area A_p and its buoyant load F_b (Figs. 12, 14, 15; eq 13)
  displaced_area  displaced area A_d(K, y_I), F_d, F-A_d correlation (Figs. 17, 18, 20; eq 14)
  shear_strength  rubble shear strength tau (eq 15), n_t/n_s, Tables 2 and 3
  summary         one CSV row per run
  make_figures    `python3 -m postproc.make_figures RESULTS_DIR` (Figs. 6-20, Tables 2-3)
  measured        `python3 -m postproc.measured CSV ...` (measured punch-through data)

The physical constants default to the paper's Table 1 values.
"""
