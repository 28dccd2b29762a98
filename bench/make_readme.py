"""Write bench/README.md from bench/results/*.json: the one place the
project's measured figures are printed.

Prose docs drift when they copy numbers (issue 27: the cost of a 300 mm paper
run was given five ways); they cite this file instead, and this file is made
from the results alone, each with the code and machine that measured it
(bench/stamps.py, else the result's own fields, else the commit that last
wrote it). Run it after a benchmark:

    /usr/bin/python3 bench/make_readme.py

tests/test_bench_readme.py checks that bench/README.md is what this writes.
"""
import glob
import json
import os
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path[:0] = [HERE, os.path.dirname(HERE)]
import stamps  # noqa: E402
from force_direction import settle_procedure  # noqa: E402
from postproc.failure_plane import mean_sd  # noqa: E402
from postproc.paper_comparison import PAPER  # noqa: E402

RESULTS = os.path.join(HERE, "results")
OUT = os.path.join(HERE, "README.md")

# What the results do not say of themselves: the scene they were measured on
# when it has changed since (facts of the measurement, kept with the generator).
EARLIER_PAPER_RIDGE = (
    "Measured on the paper scene's earlier, dense ridge 1 (419 blocks, porosity 0.14, "
    "90,950 triangles). The paper scene's ridges have since been remade as the paper's "
    "(410-413 blocks, porosity 0.26; docs/pile_and_mesh.md, \"The paper scene's piles\"): "
    "these figures are not yet measured on them.")
# runs with bonds measured before the default force direction changed (docs/model.md §3.3)
PRINTED_EQ_11 = ("Its runs took eq 11 as printed, the default force direction until 2026-11-29; the default "
                 "is now the work-conjugate form (docs/model.md §3.3), so a run of the script today makes "
                 "other figures.")
# The days those changed, and the results each concerns: a result measured
# before the day carries its note.
PAPER_RIDGES_REMADE = "2026-11-27"
FORCE_DIRECTION_CHANGED = "2026-11-29"
ON_THE_PAPER_SCENE = ("paper_cost.json", "paper_peak.json", "rigid_cost.json")
WITH_BOND_RUNS = ("paper_cost.json", "paper_peak.json", "rigid_cost.json", "runtime_vs_error.json",
                  "time_vs_error.json", "sleeping_wide.json")
# the benchmark that writes each result, where its name is not the result's
SCRIPT = {"sleeping_wide.json": "sleeping.py", "paper_peak_cuda.json": "paper_peak.py"}


def fmt(x, digits=3):
    if isinstance(x, float):
        return f"{x:.{digits}g}"
    return str(x)


def pct(x, digits=2):
    return f"{100 * x:.{digits}g} %"


def table(header, rows):
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(str(c) for c in row) + " |" for row in rows]
    return lines


def measured_on(name, data):
    """The day result `name` was measured (YYYY-MM-DD): its stamp's, its own
    field's, or else the day its file was last committed."""
    s = stamps.read().get(name)
    if s:
        return s["measured"]
    if isinstance(data, dict) and data.get("measured"):
        return str(data["measured"])[:10]
    return subprocess.run(["git", "-C", HERE, "log", "-1", "--format=%ad", "--date=short", "--",
                           os.path.join(RESULTS, name)], capture_output=True, text=True).stdout.strip()


def note(name, data):
    """What result `name` does not say of itself (above), or ''."""
    day = measured_on(name, data)
    parts = [text for names, changed, text in ((ON_THE_PAPER_SCENE, PAPER_RIDGES_REMADE, EARLIER_PAPER_RIDGE),
                                               (WITH_BOND_RUNS, FORCE_DIRECTION_CHANGED, PRINTED_EQ_11))
             if name in names and day < changed]
    return " ".join(parts)


def stamp_line(name, data):
    s = stamps.read().get(name)
    if s:
        return f"code {s['code_version']}, {s['processor']}, {s['measured']}"
    fields = data if isinstance(data, dict) else {}
    commit = subprocess.run(["git", "-C", HERE, "log", "-1", "--format=%h %ad", "--date=short", "--",
                             os.path.join(RESULTS, name)], capture_output=True, text=True).stdout.strip()
    code = fields.get("code_version") or (f"the code of commit {commit}" if commit else "not recorded")
    machine = fields.get("processor") or fields.get("machine") or "machine not recorded"
    when = fields.get("measured", "")
    return ", ".join(p for p in (code, machine, fields.get("engine_build", ""), when) if p)


def demo_reference(d):
    return [f"`icerubble demo` prints `{d['peak_line']}` ({d['samples']} samples, force record "
            f"sha256 {d['force_sha256'][:12]}..., pile `{d['pile']}`)."]


def paper_cost(d):
    rows = []
    for r in d["rows"]:
        s = r.get("settle")
        settle = f"{fmt(s['dt'] * 1e6)} µs ({pct(s['added_mass_fraction'])})" if s else "the loading's"
        rows.append([f"`{r['preset']}`", f"{fmt(r['dt'] * 1e6)} µs",
                     f"{pct(r['added_mass_fraction'])} ({r['scaled_nodes']:,} nodes)", settle,
                     f"{r['s_per_step'] * 1e3:.1f} ms", pct(r["element_share"]), f"{r['hours_20mm']:.1f} h",
                     f"{r['hours_300mm']:.1f} h"])
    return ([f"Ridge {d['ridge']}, {d['threads']} threads; 300 steps from the mesh at rest, no bond events; "
             f"the settle counted as {d['settle_time_s']} s simulated at the settle step. Wall times are "
             "projections (steps x time per step), not timed runs; a loaded pile's step costs more than "
             "this window's (a few dozen touching pairs, against ~1,000 once loaded): see the real "
             "loadings below."]
            + [""] + table(["preset", "step", "added mass", "settle step (added mass)", "time per step",
                            "element pass share", "first 20 mm", "300 mm"], rows))


def paper_peak(d):
    rest = d["rest_state"]
    # the mean force over 0.1-0.5, 0.5-1 and 1 mm to the travel (bench/paper_peak.py)
    means = [k for k in d["runs"][0] if k.startswith("F_mean_") and k.endswith("_kN_per_m")]
    rows = []
    for r in d["runs"]:
        rows.append([f"`{r['name']}`", f"{fmt(r['dt'] * 1e6)} µs", f"{r['F_m_kN_per_m']:.2f} kN/m",
                     f"{r['y_I_peak_mm']:.2f} mm",
                     " / ".join(f"{r[k]:.1f}" for k in means) + " kN/m",
                     r["n_failed"], f"{r['load_steps']:,}", f"{r['wall_load_s'] / 3600:.2f} h",
                     f"{r['wall_load_s'] / r['load_steps'] * 1e3:.2f} ms", f"{r['energy_residual_rel']:.1e}",
                     pct(r["F_m_rel_err"])])
    threads = f" ({d['threads']} CPU thread{'s' if d['threads'] > 1 else ''} a run)" if "threads" in d else ""
    return ([f"Ridge {d['ridge']}, {d['travel_mm']} mm of travel, on the {d.get('device', 'cpu').upper()}{threads}, "
             f"every run from one rest state settled "
             f"with `{rest['numerics']}` ({rest['settle_time_s']:.3f} s simulated, indenter force at rest "
             f"{rest['F_at_rest_N_per_m']:.1f} N/m); errors against `{d['reference']}`."]
            + [""] + table(["preset", "step", "F^m", "y_I at F^m", "mean F " + " / ".join(
                                k[len("F_mean_"):-len("mm_kN_per_m")].replace("_", "-") for k in means) + " mm",
                            "bond points failed", "load steps", "load time", "time per step",
                            "energy residual", "F^m error"], rows)
            + paper_peak_against(d))


def paper_peak_against(d):
    """The same load on the other device from the same rest state
    (bench/paper_peak.py --against), where one was given."""
    if "against" not in d:
        return []
    g = d["against"]
    return ["", f"The same `{g['preset']}` load from the same rest state run elsewhere ({g['processor']}, code "
                f"{g['code_version']}, {g['created'][:10]}): F^m {g['F_m_kN_per_m']:.2f} kN/m at "
                f"{g['y_I_peak_mm']:.2f} mm ({pct(g['F_m_rel_diff'])} and {g['y_I_peak_diff_mm']:.3f} mm from "
                f"the run above), {g['n_failed']} bond points failed, {g['load_steps']:,} load steps in "
                f"{g['wall_load_s'] / 3600:.2f} h ({g['wall_load_s'] / g['load_steps'] * 1e3:.2f} ms a step); "
                f"the two force records part by at most {100 * g['largest_F_diff_of_peak']:.1f} % of the peak "
                f"({'the same' if g['same_samples'] else 'other'} sample travels)."]


def paper_run_cost(cost, peak):
    """A 300 mm paper-scene run at the time per step of a real loading
    (paper_peak.json: bond events, contact lists changing) where one was run."""
    per_step = {r["name"]: r["wall_load_s"] / r["load_steps"] for r in peak["runs"]}
    rows = []
    for r in cost["rows"]:
        loading = per_step.get(r["preset"])
        rows.append([f"`{r['preset']}`", f"{r['steps_20mm'] / 1e6:.2f} M", f"{r['steps_300mm'] / 1e6:.2f} M",
                     f"{r['hours_300mm']:.1f} h",
                     f"{r['steps_20mm'] * loading / 3600:.1f} h" if loading else "not measured",
                     f"{r['steps_300mm'] * loading / 3600:.1f} h" if loading else "not measured"])
    notes = {name: note(name, d) for name, d in (("paper_cost.json", cost), ("paper_peak.json", peak))}
    stale = " ".join(f"{name}: {said}" for name, said in notes.items() if said)
    threads = f" ({peak['threads']} thread{'s' if peak['threads'] > 1 else ''} a run)" if "threads" in peak else ""
    return ([f"Steps from paper_cost.json (settle included); time per step from its 300-step window "
             f"({cost['threads']} threads), and from paper_peak.json's {peak['travel_mm']:g} mm loadings{threads} "
             "where one was run." + (" " + stale if stale else "")]
            + [""] + table(["preset", "steps to 20 mm", "steps to 300 mm", "300 mm (window)",
                            "20 mm (real loading)", "300 mm (real loading)"], rows))


def runtime_vs_error(d):
    rows = []
    for r in d["runs"]:
        e = r["errors"]
        rows.append([r["name"], fmt(r["dt_fraction"]), f"{fmt(r['dt'] * 1e6)} µs",
                     f"{r['load_element_steps'] / 1e9:.2f}", f"{r['F_m_kN_per_m']:.2f} kN/m",
                     f"{r['y_I_peak_mm']:.3f} mm",
                     " / ".join(pct(e[k], 2) for k in ("F_mean_1_5mm_rel_err", "F_mean_5_10mm_rel_err",
                                                       "F_mean_10_20mm_rel_err")),
                     pct(e["F_10mm_rel_err"]), f"{r['energy_residual_rel']:.1e}"])
    first = d["runs"][0]
    return ([f"Scene `{first['scene']}`, ridge {first['ridge']}, {first['travel_mm']} mm of travel; errors "
             "against the first run (the reference). Work in element-steps of the load phase. The "
             "reference's F^m is a late event; the others' is the first peak (docs/speed_and_accuracy.md)."]
            + [""] + table(["run", "step fraction", "step", "work (1e9 element-steps)", "F^m", "y_I at F^m",
                            "mean F error 1-5 / 5-10 / 10-20 mm", "F error at 10 mm", "energy residual"],
                           rows))


def sleeping(d):
    rows = []
    for r in d["runs"]:
        e = r["errors"]
        rows.append([r["name"], pct(r["element_fraction"], 3), pct(e["F_m_rel_err"]),
                     pct(e["F_mean_10_20mm_rel_err"]), f"{r['wall_load_s']:.0f} s"])
    first = d["runs"][0]
    return ([f"Scene `{first['scene']}`, ridge {first['ridge']}, `{first['numerics']}`, "
             f"{first['travel_mm']} mm; errors against the run without sleeping."]
            + [""] + table(["run", "element-steps computed", "F^m error", "mean F error 10-20 mm",
                            "load time"], rows))


def rigid_cost(d):
    share = d["engine_s_per_step"]
    return [f"{d['blocks']} blocks, {d['bond_pairs']:,} bond pairs, {d['threads']} thread, step "
            f"{d['dt'] * 1e6:.0f} µs: {d['s_per_step'] * 1e3:.0f} ms per step, of which YADE's "
            f"InteractionLoop {pct(share['InteractionLoop'] / d['s_per_step'])} and the coupling (PyRunner) "
            f"{pct(share['PyRunner'] / d['s_per_step'])}; hulls add {pct(d['hull_added_area'])} of a block's area."]


def bonds(d):
    rows = [[c["case"], c["triangles"], c["bond_points"], c["screen_interval"], f"{c['checks_per_step']:.1f}",
             f"{c['bond_us_per_step']:.1f} µs", f"{c['step_us']:.0f} µs", pct(c["bond_share"])]
            for c in d["cases"]]
    return ([f"Screening gain {d['screening_gain']:.1f}x. {d.get('note', '')}"]
            + [""] + table(["case", "triangles", "bond points", "screen interval", "checks per step",
                            "bond check per step", "step", "bond share"], rows))


def collision(d):
    rows = [[r["triangles"], r["threads"], f"{r['triangle_steps_per_s'] / 1e6:.1f} M",
             f"{r['engine_bytes_per_triangle']:.0f}", f"{r['energy_residual_over_initial']:.1e}"] for r in d]
    return table(["triangles", "threads", "triangle-steps per s", "engine bytes per triangle",
                  "energy residual"], rows)


def time_vs_error(d):
    coll = [[fmt(r["dt_fraction"]), f"{r['dt'] * 1e6:.3f} µs", r["steps"], f"{r['energy_error']:.1e}"]
            for r in d if r["case"] == "collision"]
    wave = [[r["cells"], fmt(r["h"]), f"{r['wave_speed_error']:.1e}"] for r in d if r["case"] == "wave"]
    return (["Two blocks colliding:", ""] + table(["step fraction", "step", "steps", "energy error"], coll)
            + ["", "A bar's wave:", ""] + table(["cells", "h (m)", "wave speed error"], wave))


def cores_said(d):
    """The machine's processors as the result records them: logical
    processors only (cpu_count) before the topology was recorded."""
    t = d.get("cpu_topology")
    if not t:
        return f"{d['cpu_count']} cores"
    place = (f", OMP_PLACES={t['omp_places']} OMP_PROC_BIND={t['omp_proc_bind']}"
             if t["omp_places"] or t["omp_proc_bind"] else "")
    return (f"{t['logical']} logical processors on {t['cores']} cores as /proc/cpuinfo lists them "
            f"({t['threads_per_core']:g} a core{place})")


def element_pass_by_thread(r):
    """The element pass's busiest thread against the mean, and the mean wait
    at its barrier (recorded since 2026-12-01; older records: "-")."""
    busy, wait = r.get("element_busy_ms"), r.get("element_wait_ms")
    if not busy or not sum(busy) > 0.0:
        return ["-", "-"]
    return [f"{max(busy) / (sum(busy) / len(busy)):.2f}", f"{sum(wait) / len(wait):.3f} ms"]


def gpu_body_forces(d):
    base = d["cpu"][0]
    rows = [[r["threads"], fmt(r["ms_per_step"]), f"{base['ms_per_step'] / r['ms_per_step']:.2f}",
             f"{100 * base['ms_per_step'] / r['ms_per_step'] / (r['threads'] / base['threads']):.0f} %",
             fmt(r["elements_ms"]), fmt(r["drag_ms"]), fmt(r["contact_detection_ms"] + r["contact_forces_ms"]),
             fmt(r["integration_ms"])] + element_pass_by_thread(r) for r in d["cpu"]]
    lines = [f"The {d['scene']} scene's mesh `{d['mesh']}` ({d['n_triangles']:,} triangles, {d['n_nodes']:,} nodes), "
             f"load phase, `{d['preset']}` numerics, on {cores_said(d)}"
             + (" (the run was stopped before its end: what it measured up to then)" if d.get("complete") is False
                else "") + ":", ""]
    by_thread = ["element pass: busiest thread / mean", "element pass: mean wait at its barrier"]
    lines += table(["threads", "ms per step", "speed-up", "efficiency", "elements (ms)", "of which drag",
                    "contact", "integration"] + by_thread, rows)
    if d.get("cpu_loaded"):
        lo = d["cpu_loaded"]
        b = lo[0]
        lines += ["", f"The same mesh loaded: every node nudged by up to 0.1 mm, its bond points split, then stepped "
                  f"until the splits were over ({lo[-1]['touching_pairs']:,} touching pairs, against a few dozen "
                  f"above):", ""]
        # friction is timed apart since 2026-12-01 (older records: "-")
        lines += table(["threads", "ms per step", "speed-up", "efficiency", "elements (ms)", "contact forces",
                        "of which friction", "integration", "splits"] + by_thread,
                       [[r["threads"], fmt(r["ms_per_step"]), f"{b['ms_per_step'] / r['ms_per_step']:.2f}",
                         f"{100 * b['ms_per_step'] / r['ms_per_step'] / (r['threads'] / b['threads']):.0f} %",
                         fmt(r["elements_ms"]), fmt(r["contact_forces_ms"]),
                         fmt(r["friction_ms"]) if "friction_ms" in r else "-", fmt(r["integration_ms"]), r["splits"]]
                        + element_pass_by_thread(r) for r in lo])
    if d.get("triad_GBps"):
        lines += ["", "Memory bandwidth (STREAM triad, bench/stream_triad.cpp), GB/s: "
                  + "; ".join(f"{t['threads']} threads {t['GBps']:.0f} ({t['mb_per_array']:.0f} MB arrays)"
                              for t in d["triad_GBps"])]
    g = d.get("gpu")
    if g:
        ok = g["compare"]["ok"]
        stages = ", ".join(f"{k} {v:.1f}" for k, v in g["stages_us"].items())
        lines += ["", f"GPU ({g['device']}): the body-force stage (elements, water, node gather; "
                  f"icerubble/engine/gpu.py) takes {g['body_forces_us']:.1f} µs per evaluation (a CUDA graph); "
                  f"its kernels launched one by one: {stages} µs. Against the CPU's elements part: "
                  + ", ".join(f"{r['elements_ms'] * 1e3 / g['body_forces_us']:.0f}× {r['threads']} threads"
                              for r in d["cpu"])
                  + f". Fields as the CPU's: {'yes' if ok else 'NO'} (element and buoyancy fields bit for bit, "
                  f"quadratic drag and the energy sum to {max(g['compare']['drag_k'][1], g['compare']['elastic_energy'][1]):.1e})."]
        if "node_update_us" in g:
            lines += ["", f"GPU: the node update (central difference and the ledger's sums; its positions and "
                      f"velocities the CPU's bits, tools/gpu_check.py) takes {g['node_update_us']:.1f} µs, against "
                      f"{d['cpu'][-1]['integration_ms'] * 1e3:.0f} µs for the integration part at "
                      f"{d['cpu'][-1]['threads']} threads."]
        if "contact_normal_us" in g:
            lines += ["", f"GPU: the normal contact pass ({g['contact_candidates']:,} candidate pairs; the contact "
                      f"forces the CPU's bits) takes {g['contact_normal_us']:.1f} µs, against "
                      f"{d['cpu'][-1]['contact_forces_ms'] * 1e3:.0f} µs for the contact forces part (friction "
                      f"included) at {d['cpu'][-1]['threads']} threads."]
        if "search_us" in g:
            lines += ["", f"GPU: the contact search of a list rebuild (the CPU's candidates and layout, "
                      f"tools/gpu_check.py) takes {g['search_us']:.1f} µs, its wait for the count included, "
                      f"against {g['search_cpu_ms']:.2f} ms for the CPU's search and layout on one thread."]
        if "friction_us" in g:
            lines += ["", f"GPU: friction ({g['friction_pairs']:,} touching pairs in {g['friction_colours']} colours; "
                      f"coloured, solved and summed on the GPU with the CPU's colours and bits, tools/gpu_check.py) "
                      f"takes {g['friction_us']:.1f} µs (bench/gpu_friction.py times it with many pairs)."]
        if "bond_check_us" in g:
            lines += ["", f"GPU: the bond check of all {g['bond_points_intact']:,} intact bond points (eqs 5-7; "
                      f"ratios, tractions and split plan the CPU's) takes {g['bond_check_us']:.1f} µs, against "
                      f"{d['cpu'][-1]['bonds_ms'] * 1e3:.0f} µs for the bonds part (screened checks and the "
                      f"cohesive forces) at {d['cpu'][-1]['threads']} threads."]
        if "cohesive_us" in g:
            c = g["cohesive_cpu"]
            lines += ["", f"GPU: the cohesive forces of {g['cohesive_pairs']:,} opened pairs (eqs 8-12, after "
                      f"{g['cohesive_points_split']:,} points split in the mesh with every node nudged by up to "
                      f"0.1 mm; per pair and per node the CPU's bits) take {g['cohesive_us']:.1f} µs. The CPU's "
                      f"bonds part over 20 steps of that state took {c['bonds_ms']:.0f} ms a step at "
                      f"{c['threads']} threads, nearly all of it the splits of points still reaching eq 5 "
                      f"(topology changes, on the host in either backend): the CPU's cohesive pass is not timed "
                      f"apart."]
        if "whole_step_us" in g:
            lines += ["", f"GPU: whole steps (gpu.Steps) of that state, {g['whole_steps']:,} of them with "
                      f"{g['whole_host_steps']} taken by the model on the host ("
                      + ("splits" if "whole_list_rebuilds" in g else "splits, list rebuilds")
                      + ", each "
                      f"followed by the stages made again"
                      + (f": {g['whole_host_step_s']:.2f} s in those steps, {g['whole_make_s']:.2f} s making the stages"
                         if "whole_make_s" in g else "")
                      + (f"; {g['whole_list_rebuilds']} candidate lists rebuilt in place, {g['whole_list_s']:.2f} s"
                         if "whole_list_rebuilds" in g else "")
                      + f"), took {g['whole_step_us']:.0f} µs a step (wall), against "
                      + ", ".join(f"{fmt(r['ms_per_step'])} ms at {r['threads']} threads" for r in d["cpu"])
                      + " (the load phase before the nudge). gpu_step_profile.json says where it goes."]
    return lines


def split_step(d):
    rows = [[r["threads"], fmt(r["plain_ms"]), fmt(r["split_step_ms"]), f"{r['splits_per_step']:.0f}",
             f"{r['split_step_ms'] / r['plain_ms']:.1f}"] for r in d["rows"]]
    return [f"A step in which bond points split, on the {d['scene']} scene's mesh `{d['mesh']}` "
            f"({d['n_triangles']:,} triangles, `{d['preset']}` numerics), right after every node was nudged "
            f"by up to 0.1 mm (bench/split_step.py): the model rebuilds topology, masses and stable step "
            f"before the next step, and the GPU backend takes such a step on the host.", ""] + table(
        ["threads", "plain step (ms)", "step with splits (ms)", "points split a step", "ratio"], rows)


def gpu_step_profile(d):
    code = f" (code {d['code_version']})" if "code_version" in d else ""
    lines = [f"Whole GPU steps of `{d['mesh']}` in the load phase on {d['device']}{code}, each kernel's duration "
             f"(Nsight Compute's hardware timer), per step:", ""]
    states = list(d["states"])
    names = []
    for st in states:
        for r in d["states"][st]["kernels"]:
            if r["kernel"] not in names:
                names.append(r["kernel"])
    per = {st: {r["kernel"]: r for r in d["states"][st]["kernels"]} for st in states}
    rows = [[f"`{n}`"] + [fmt(per[st][n]["us_per_step"]) if n in per[st] else "" for st in states] for n in names[:12]]
    rows.append(["all kernels"] + [f"{d['states'][st]['us_per_step']:.0f}" for st in states])
    return lines + table(["kernel"] + [f"{st} (µs per step)" for st in states], rows)


def deep_vs_paper(d):
    u = d["set_up"]
    rows = [[r["ridge"], r["variant"], r.get("settle_bonds", "checked"), r.get("side_walls", "free"),
             f"{r['n_triangles']:,}",
             f"{r['first_peak_kN_per_m']:.1f} at {r['y_I_first_peak_mm']:.2f}" if "first_peak_kN_per_m" in r else "",
             f"{r['F_m_kN_per_m']:.1f} at {r['y_I_peak_mm']:.2f}",
             f"{r['alpha_mean_1_20mm_deg']:.1f} ± {r['alpha_sd_1_20mm_deg']:.1f}", f"{r['A_p_mean_1_20mm_m2']:.0f}",
             f"{r['F_20mm_kN_per_m']:.1f}", r.get("n_split_settle", ""),
             f"{r['settle_time_s']:.2f} s, " + (f"{r['wall_settle_s'] / 60:.0f} min" if r["wall_settle_s"] >= 1 else
                                                   # before c59cda7 a resumed run kept its last process's wall
                                                   # times: a settle resumed into its loading shows ~0 s
                                                   "wall not kept (resumed)"), f"{r['wall_load_s'] / 60:.0f} min",
             r.get("code_version", "")] for r in d["runs"]]
    return ([f"Set-up: μ {u['mu']}, τ_cr {u['tau_cr'] / 1e3:g} kPa, "
             f"`{u['numerics']}` numerics, to {u['target_travel'] * 1e3:g} mm. First peak: the largest F before "
             "1 mm; F^m: the largest F over the first 5 mm (postproc/loads.py). α and A_p: means over y_I = "
             "1-20 mm through the split points. Wall times on one or two shared cores (the run's own record).", ""]
            + table(["ridge", "variant", "bonds while settling", "side walls", "triangles", "first peak (kN/m at mm)", "F^m (kN/m at mm)", "α (°)",
                     "A_p (m²)", "F(20 mm) (kN/m)", "points split settling", "settle (simulated, wall)",
                     "load 20 mm (wall)", "code"], rows))


def gpu_friction(d):
    lines = [f"A wall of {d['rows']} × {d['cols']} pressed blocks ({d['n_triangles']:,} triangles): "
             f"{d['touching_pairs']:,} touching pairs in {d['colours']} colours. The CPU's friction "
             f"({d.get('cpu_threads', 1)} thread{'s' if d.get('cpu_threads', 1) > 1 else ''}) "
             f"takes {fmt(d['cpu_ms'])} ms."]
    g = d.get("gpu")
    if g:
        lines[0] += (f" On the GPU ({g['device']}): {g['friction_us']:.1f} µs, {d['cpu_ms'] * 1e3 / g['friction_us']:.0f}× "
                     f"the CPU, the colouring in {g['rounds']} parallel rounds; the CPU's colours and bits: "
                     f"{'yes' if g['same'] else 'NO'}.")
    else:
        lines[0] += " No GPU was visible where it was measured."
    return lines


def force_direction(d):
    rows = []
    for r in d["runs"]:
        t3 = d.get("table_3", {}).get(f"{r['tau_cr_kPa']:.1f}")
        t3 = f"{t3[0]:g} ± {t3[1]:g}" if t3 else ""
        direction = r["force_direction"] + (", indenter held while settling" if r.get("settle_indenter") == "held" else "")
        rows.append([r["ridge"], r["mu"], fmt(r["tau_cr_kPa"]), f"{r['y_I_end_mm']:.0f}", direction,
                     f"{r['first_peak_kN_per_m']:.1f} at {r['y_I_first_peak_mm']:.2f}",
                     f"{r['F_m_kN_per_m']:.1f} at {r['y_I_peak_mm']:.2f}",
                     f"{r['alpha_mean_1_20mm_deg']:.1f} ± {r['alpha_sd_1_20mm_deg']:.1f}",
                     f"{r['A_p_mean_1_20mm_m2']:.0f}", f"{r['F_20mm_kN_per_m']:.1f}",
                     f"{r['F_15_20mm_mean_kN_per_m']:.1f}" if "F_15_20mm_mean_kN_per_m" in r else "",
                     f"{r['n_split']} / {r['n_failed']}", f"{r['n_t']}/{r['n_s']} = {fmt(r['nt_ns'])}",
                     f"{r['n_t_init']}/{r['n_s_init']}", t3, r.get("code_version", "")])
    return (["Runs of the paper-depth `deep` scene (`fast` numerics, bonds checked while settling) to "
             "y_I = 20 mm (Figs. 8-15) or 300 mm (Table 3). First peak: the largest F before 1 mm; F^m: the largest F over the first 5 mm. "
             "α and A_p: means over y_I = 1-20 mm through the split points. F(20 mm): one sample; the mean F over "
             "15-20 mm is the steadier measure of the load after the peak. Points split / fully failed while "
             "loading; n_t/n_s: the failure mode at full failure within the run's travel (Table 3's count; the "
             "paper's is over 300 mm), and the side of eq 6 each point split on (initiation).", ""]
            + table(["ridge", "μ", "τ_cr (kPa)", "travel (mm)", "force direction", "first peak (kN/m at mm)",
                     "F^m (kN/m at mm)", "α (°)", "A_p (m²)", "F(20 mm) (kN/m)", "mean F 15-20 mm (kN/m)",
                     "split / failed",
                     "n_t/n_s at full failure", "n_t/n_s at initiation", "Table 3 (300 mm)", "code"], rows)
            + force_direction_long(d) + force_direction_table3(d) + force_direction_friction(d))


def force_direction_long(d):
    """The runs beyond 20 mm: how their count moves with the travel, their mean F and record maximum."""
    long = [r for r in d["runs"] if "F_record_max_kN_per_m" in r]
    if not long:
        return []
    rows = [[r["ridge"], r["mu"], fmt(r["tau_cr_kPa"]), f"{r['y_I_end_mm']:.0f}", r["force_direction"],
             f"{r['n_t_within_20mm']}/{r['n_s_within_20mm']}", f"{r['n_t_within_100mm']}/{r['n_s_within_100mm']}",
             f"{r['n_t']}/{r['n_s']} = {fmt(r['nt_ns'])}",
             f"{r.get('F_mean_20_150mm_kN_per_m', float('nan')):.1f}",
             f"{r.get('F_mean_150_300mm_kN_per_m', float('nan')):.1f}",
             f"{r['F_record_max_kN_per_m']:.1f} at {r['y_I_record_max_mm']:.1f}"] for r in long]
    return (["", "The runs beyond 20 mm: n_t/n_s at full failure within 20 and 100 mm and over the whole "
             "travel, the mean F over 20-150 and 150-300 mm (the paper's intervals, as postproc/summary.py takes them), and the record's maximum.", ""]
            + table(["ridge", "μ", "τ_cr (kPa)", "travel (mm)", "force direction", "n_t/n_s within 20 mm",
                     "within 100 mm", "over the travel", "mean F 20-150 mm (kN/m)", "mean F 150-300 mm (kN/m)",
                     "record max (kN/m at mm)"], rows))


def force_direction_table3(d):
    """Table 3's own design, ridge by ridge: n_t/n_s at full failure over 300 mm at μ 0.05, one
    row per τ_cr, each cell with its distance from Table 3's mean in Table 3's sd."""
    table3 = d.get("table_3", {})
    runs = {}
    for r in d["runs"]:
        if r["y_I_end_mm"] >= 299.5 and abs(r["mu"] - 0.05) < 1e-9:
            runs.setdefault(r["force_direction"], {})[(r["tau_cr_kPa"], r["ridge"])] = r
    lines = []
    for direction, cases in sorted(runs.items()):
        ridges = sorted({k[1] for k in cases})
        rows = []
        for tau in sorted({k[0] for k in cases}):
            paper = table3.get(f"{tau:.1f}")
            cells, ratios = [], []
            for ridge in ridges:
                r = cases.get((tau, ridge))
                if r is None:
                    cells.append("")
                    continue
                ratios.append(r["nt_ns"])
                z = f" ({(r['nt_ns'] - paper[0]) / paper[1]:+.1f} sd)" if paper else ""
                cells.append(f"{r['n_t']}/{r['n_s']} = {r['nt_ns']:.2f}{z}")
            m, sd = mean_sd(ratios)
            mean = f"{m:.2f} ± {sd:.2f} (n={len(ratios)})" if len(ratios) > 1 else ""
            rows.append([fmt(tau)] + cells + [mean, f"{paper[0]:g} ± {paper[1]:g}" if paper else ""])
        lines += ["", f"Table 3's count, ridge by ridge: n_t/n_s at full failure over 300 mm, μ 0.05, {direction} "
                      "(in brackets: the distance from Table 3's mean in Table 3's sd):", ""]
        lines += table(["τ_cr (kPa)"] + [f"ridge {k}" for k in ridges] + ["mean ± sd over ridges", "Table 3"], rows)
    return lines


def force_direction_friction(d):
    """μ 0.3 against μ 0.05 on each ridge where both ran from one settle procedure (Fig. 8, Table 3's
    τ ratio): runs that settled differently are not paired, since the procedure alone moved a first
    peak by 14 % (docs/study_paper_depth.md). A case run to 20 and 300 mm from one rest state is
    read from its shorter run (the same first peak and 15-20 mm window)."""
    cases = {}
    for r in sorted(d["runs"], key=lambda r: r["y_I_end_mm"]):
        key = (r["force_direction"], r["tau_cr_kPa"], settle_procedure(r))
        cases.setdefault(key, {}).setdefault(r["ridge"], {}).setdefault(r["mu"], r)
    lines = []
    for (direction, tau, (bonds, indenter, walls)), ridges in sorted(cases.items()):
        pairs = {k: v for k, v in sorted(ridges.items()) if 0.05 in v and 0.3 in v}
        if not pairs:
            continue
        rows, peak_ratio, late_ratio = [], [], []
        for ridge, by_mu in pairs.items():
            lo, hi = by_mu[0.05], by_mu[0.3]
            peak_ratio.append(hi["first_peak_kN_per_m"] / lo["first_peak_kN_per_m"])
            late = [m.get("F_15_20mm_mean_kN_per_m", float("nan")) for m in (lo, hi)]
            late_ratio.append(late[1] / late[0])
            rows.append([ridge, f"{lo['first_peak_kN_per_m']:.1f} / {hi['first_peak_kN_per_m']:.1f}",
                         f"{peak_ratio[-1]:.2f}", f"{late[0]:.1f} / {late[1]:.1f}", f"{late_ratio[-1]:.2f}"])
        if len(pairs) > 1:
            (pm, ps), (lm, ls) = mean_sd(peak_ratio), mean_sd(late_ratio)
            rows.append(["mean ± sd", "", f"**{pm:.2f} ± {ps:.2f}**", "", f"{lm:.2f} ± {ls:.2f}"])
        paper = PAPER["tau_ratio"]["tau1"].get(tau)   # keyed 5, 50, 100: 5.0 finds 5
        if paper:
            rows.append(["Table 3 (τ^(1))", "", paper, "", ""])
        lines += ["", f"μ 0.3 against μ 0.05 at τ_cr {fmt(tau)} kPa, {direction}, indenter {indenter} while "
                      f"settling at both μ (bonds {bonds}, side walls {walls}; "
                      f"{len(pairs)} ridge{'s' if len(pairs) > 1 else ''}):", ""]
        lines += table(["ridge", "first peak μ 0.05 / μ 0.3 (kN/m)", "ratio", "mean F 15-20 mm μ 0.05 / μ 0.3 (kN/m)",
                        "ratio"], rows)
    return lines


def touching_churn(d):
    # islands recorded since 2026-12-01 (older records: "-")
    rows = [[f"{w['load_steps_before']:,}", f"{w['points_split']:,}", w["steps"],
             f"{w['touching_min']:,}-{w['touching_max']:,}", f"{w['steps_changed']:,}",
             " / ".join(fmt(q) for q in w["steps_between_changes_p10_p50_p90"]),
             f"{w['islands_at_end']:,} ({w['largest_island_at_end']} of {w['touching_at_end']:,})"
             if "islands_at_end" in w else "-"] for w in d["windows"]]
    return ([f"The paper scene (ridge {d['ridge']}, `{d['preset']}`) loaded from `{d['rest_state']}`:"
             ""] + [""] + table(["load steps before", "points split", "steps", "touching pairs",
                                 "steps where they changed", "steps between changes (10th / 50th / 90th pct)",
                                 "islands at the end (the largest's pairs of all)"],
                                rows))


FORMATS = {"demo_reference.json": demo_reference, "touching_churn.json": touching_churn, "paper_cost.json": paper_cost, "paper_peak.json": paper_peak,
           "paper_peak_cuda.json": paper_peak,
           "runtime_vs_error.json": runtime_vs_error, "sleeping_wide.json": sleeping,
           "rigid_cost.json": rigid_cost, "bonds.json": bonds, "collision.json": collision,
           "time_vs_error.json": time_vs_error, "gpu_body_forces.json": gpu_body_forces,
           "split_step.json": split_step,
           "gpu_friction.json": gpu_friction, "gpu_step_profile.json": gpu_step_profile,
           "deep_vs_paper.json": deep_vs_paper, "force_direction.json": force_direction}


def title(script):
    """The first line of a benchmark's docstring."""
    path = os.path.join(HERE, script)
    if not os.path.exists(path):
        return ""
    with open(path) as f:
        text = f.read()
    doc = text.split('"""')[1] if text.startswith('"""') else ""
    return " ".join(doc.split("\n\n")[0].split())


def section(name, data):
    script = SCRIPT.get(name, name.replace(".json", ".py"))
    lines = [f"## {name}", "", f"`bench/{script}`: {title(script)}", "",
             f"Measured with: {stamp_line(name, data)}.", ""]
    said = note(name, data)
    if said:
        lines += [f"**Note.** {said}", ""]
    fmt_ = FORMATS.get(name)
    body = fmt_(data) if fmt_ else ["```", json.dumps(data, indent=1)[:2000], "```"]
    figure = name.replace(".json", ".png")
    if os.path.exists(os.path.join(RESULTS, figure)):
        body += ["", f"Figure: [results/{figure}](results/{figure})."]
    return lines + body + [""]


def render():
    loaded = {}
    for path in sorted(glob.glob(os.path.join(RESULTS, "*.json"))):
        name = os.path.basename(path)
        if name == os.path.basename(stamps.STAMPS):
            continue
        with open(path) as f:
            loaded[name] = json.loads(f.read().replace("NaN", "null"))
    lines = ["# Measured figures", "",
             "Generated by `bench/make_readme.py` from `bench/results/*.json`: do not edit; run",
             "`/usr/bin/python3 bench/make_readme.py` after a benchmark. Each result says which code",
             "and machine measured it. Wall times depend on the machine and its load (this project's",
             "2-core machine varies by ~30 % between sessions); element-steps and step counts do not.", "",
             "Contents: " + ", ".join(f"[{n}](#{n.replace('.', '')})" for n in loaded)
             + (", [a 300 mm paper-scene run](#a-300-mm-paper-scene-run)"
                if {"paper_cost.json", "paper_peak.json"} <= set(loaded) else ""), ""]
    for name, data in loaded.items():
        lines += section(name, data)
    if {"paper_cost.json", "paper_peak.json"} <= set(loaded):
        lines += ["## A 300 mm paper-scene run", ""]
        lines += paper_run_cost(loaded["paper_cost.json"], loaded["paper_peak.json"]) + [""]
    return "\n".join(lines)


if __name__ == "__main__":
    with open(OUT, "w") as f:
        f.write(render())
    print(f"wrote {os.path.relpath(OUT)}")
