#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Figures and index.html of a storm run's damage report (issue 9; docs/report.md).

    report.py REPORT_DIR [--run RUN_DIR]

Reads what `armour report` wrote into REPORT_DIR (units.csv, timeseries.csv, storm.csv,
summary.json) and writes there:

  plan.png              plan view (x, y): each unit's displacement vector from its initial to its
                        final centroid, coloured by displacement / Dn (seed 000 Figs. 7, 8, 10, 11)
  elevation.png         the same seen from the side (x, z), with the still water level
  total_displacement.png  total displacement of all units against time, and the counts of units
                        moved more than 0.2, 0.5 and 1 Dn (seed 000 Figs. 9, 12)
  displacement_hist.png histogram of displacement / Dn with the 0.2, 0.5 and 1 Dn marks
  storm.png             the storm input at the run's times: pressure at the chosen voxel (seed 000
                        Fig. 5) and the free surface at the gauge (when there is a storm)
  index.html            the tables (damage measures, P2, storm, design formulas beside the
                        simulated damage), the figures, and a link to the run's bodies.pvd
  paraview_state.py     a ParaView Python state: bodies.pvd coloured by displacement (3D animation)

Runs headless (Agg backend). Needs python3-numpy and python3-matplotlib (Debian).
"""
import argparse
import csv
import html
import json
import math
import os
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def read_csv(path):
    """Columns by header name: numbers as float arrays, other columns as lists of strings."""
    if not path.exists():
        sys.exit(f"{path}: missing; run `armour report RUN_DIR` first")
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        return {}
    cols = {}
    for key in rows[0].keys():
        values = [r[key] for r in rows]
        try:
            cols[key] = np.asarray([float(v) for v in values])
        except ValueError:
            cols[key] = values
    return cols


def vector_plot(units, h, v, xlabel, ylabel, title, out, swl=None):
    fig, ax = plt.subplots(figsize=(8, 6))
    h0, v0, h1, v1 = units[h + "0"], units[v + "0"], units[h], units[v]
    dn = units["displacement_dn"]
    vmax = max(1.0, float(np.nanmax(dn))) if len(dn) else 1.0
    norm = matplotlib.colors.Normalize(0.0, vmax)
    ax.scatter(h0, v0, s=12, c="0.6", label="initial centroid", zorder=1)
    q = ax.quiver(h0, v0, h1 - h0, v1 - v0, dn, cmap="plasma", norm=norm, angles="xy", scale_units="xy", scale=1.0,
                  width=0.004, zorder=2)
    ax.scatter(h1, v1, s=16, c=dn, cmap="plasma", norm=norm, edgecolor="k", linewidth=0.3, zorder=3,
               label="final centroid")
    fig.colorbar(q, ax=ax, label="displacement / Dn (-)")
    if swl is not None and math.isfinite(swl):
        ax.axhline(swl, color="tab:blue", linestyle="--", linewidth=0.8, label="still water level")
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_title(title)
    ax.legend(loc="best", fontsize=8)
    fig.tight_layout()
    fig.savefig(out, dpi=120)
    plt.close(fig)


def write_paraview_state(path, pvd):
    """A ParaView Python state: the run's bodies.pvd coloured by displacement magnitude (and its
    fixed_bodies.vtp in grey, if there is one), the time slider on the frames' times. Written as
    text; ParaView is not needed to write it."""
    text = f"""# ParaView Python state of an armour damage report (docs/report.md).
# Load with File > Load State (state file type: Python state), or run: paraview --state=paraview_state.py
import os
from paraview.simple import *  # noqa: F401,F403

bodies = PVDReader(FileName={str(pvd)!r})
RenameSource("bodies", bodies)
view = GetActiveViewOrCreate("RenderView")
if os.path.exists({str(pvd.with_name("fixed_bodies.vtp"))!r}):  # the fixed bodies, written once
    fixed = XMLPolyDataReader(FileName=[{str(pvd.with_name("fixed_bodies.vtp"))!r}])
    RenameSource("fixed bodies", fixed)
    Show(fixed, view).DiffuseColor = [0.6, 0.6, 0.6]
display = Show(bodies, view)
ColorBy(display, ("POINTS", "displacement", "Magnitude"))
display.SetScalarBarVisibility(view, True)
GetAnimationScene().UpdateAnimationUsingDataTimeSteps()
GetAnimationScene().AnimationTime = GetAnimationScene().EndTime
display.RescaleTransferFunctionToDataRange(False, True)
view.CameraPosition = [0.0, -1.0, 0.4]
view.CameraFocalPoint = [0.0, 0.0, 0.0]
view.CameraViewUp = [0.0, 0.0, 1.0]
view.ResetCamera()
Render()
"""
    tmp = path.with_name(path.name + f".tmp.{os.getpid()}")
    tmp.write_text(text)
    tmp.replace(path)


def stress_section(run, folder, figures, table, fmt):
    """The units' stresses, when `armour stress` has analysed the run (RUN/stress/): a table and a
    figure of the largest body stress per unit against the tensile strength."""
    units_csv, summary_json = run / "stress" / "units.csv", run / "stress" / "summary.json"
    if not units_csv.exists() or not summary_json.exists():
        return ["<h2>Stress in the units</h2>",
                "<p>Not analysed: record the units' loads (<code>--set 'output.unit_loads=[unit_*]'</code>) and run "
                "<code>armour stress RUN_DIR</code> before the report (docs/user-guide.md).</p>"]
    st = json.loads(summary_json.read_text())
    strength = float(st["strength_pa"])
    with open(units_csv, newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        return []
    rows.sort(key=lambda r: -float(r["max_body_sigma1_pa"]))
    names = [r["name"] for r in rows]
    body = [float(r["max_body_sigma1_pa"]) / 1e6 for r in rows]
    fig, ax = plt.subplots(figsize=(8, 3.5))
    ax.bar(range(len(rows)), body, color=["#c0392b" if b > strength / 1e6 else "#2e86c1" for b in body])
    ax.axhline(strength / 1e6, color="k", ls="--", lw=1, label=f"tensile strength {strength / 1e6:.3g} MPa")
    ax.set_xticks(range(len(rows)), names, rotation=90, fontsize=7)
    ax.set_ylabel("largest body tension (MPa)")
    ax.set_title("largest tension in each unit, away from its contacts (armour stress)")
    ax.legend()
    fig.tight_layout()
    fig.savefig(folder / "stress.png", dpi=120)
    plt.close(fig)
    figures.append(("stress.png", "Largest tension in each unit away from its contacts, against the tensile strength"))
    over = sum(1 for b in body if b > strength / 1e6)
    table_rows = [[html.escape(r["name"]), fmt(float(r["max_body_sigma1_pa"]) / 1e6), fmt(float(r["time_s"])),
                   html.escape(r["event"]), fmt(float(r["max_sigma1_pa"]) / 1e6),
                   "<b>above</b>" if r["over_strength"] == "1" else "below"] for r in rows[:20]]
    m = st.get("model", {})
    return ["<h2>Stress in the units</h2>",
            f"<p>{over} of {len(rows)} analysed units above the tensile strength {strength / 1e6:.3g} MPa "
            f"(tet{10 if m.get('order') == 2 else 4} meshes, contact forces spread over {fmt(m.get('spread_radius_dn'))} "
            f"Dn; body stress at least {fmt(m.get('away_dn'))} Dn from every contact). Impact stresses scale with "
            "the square root of the contact stiffness (docs/fidelity.md, \"Stress from a rigid replay\"). "
            "Map: <code>stress/stress_map.vtp</code> in ParaView.</p>",
            table(table_rows, ["unit", "body tension (MPa)", "at t (s)", "event", "at a contact (MPa)", "strength"])]


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("folder", type=Path)
    parser.add_argument("--run", type=Path, default=None, help="the run folder (for the bodies.pvd link)")
    a = parser.parse_args()
    folder = a.folder
    summary_path = folder / "summary.json"
    if not summary_path.exists():
        sys.exit(f"{summary_path}: missing; run `armour report RUN_DIR` first")
    with open(summary_path) as f:
        summary = json.load(f)
    units = read_csv(folder / "units.csv")
    series = read_csv(folder / "timeseries.csv")
    storm_path = folder / "storm.csv"
    storm = read_csv(storm_path) if storm_path.exists() and storm_path.stat().st_size > 0 else {}
    figures = []

    if units:
        vector_plot(units, "x", "y", "x, onshore (m)", "y, along the trunk (m)",
                    "plan: displacement vectors coloured by displacement / Dn", folder / "plan.png")
        figures.append(("plan.png", "Plan view of the displacement vectors (seed 000 Figs. 7, 8, 10, 11)"))
        vector_plot(units, "x", "z", "x, onshore (m)", "z, up (m)",
                    "elevation: displacement vectors coloured by displacement / Dn", folder / "elevation.png",
                    swl=summary.get("storm", {}).get("still_water_level_m"))
        figures.append(("elevation.png", "Elevation (side view) of the displacement vectors"))
        fig, ax = plt.subplots(figsize=(7, 4))
        dn = units["displacement_dn"]
        top = max(1.2, float(np.nanmax(dn)) * 1.05) if len(dn) else 1.2
        ax.hist(dn, bins=np.linspace(0.0, top, 25), color="tab:gray", edgecolor="k")
        for mark in (0.2, 0.5, 1.0):
            ax.axvline(mark, color="tab:red", linestyle="--", linewidth=0.8)
        ax.set_xlabel("displacement / Dn (-)")
        ax.set_ylabel("units")
        ax.set_title("displacement of the units over the run")
        fig.tight_layout()
        fig.savefig(folder / "displacement_hist.png", dpi=120)
        plt.close(fig)
        figures.append(("displacement_hist.png", "Histogram of displacement / Dn, marks at 0.2, 0.5, 1 Dn"))

    if series:
        fig, (ax, bx) = plt.subplots(2, 1, figsize=(8, 6), sharex=True)
        ax.plot(series["time_s"], series["total_displacement_m"], color="k")
        ax.set_ylabel("total displacement of all units (m)")
        ax.set_title("evolution of the total displacement (seed 000 Figs. 9, 12)")
        for key, label in (("moved_0.2dn", "> 0.2 Dn"), ("moved_0.5dn", "> 0.5 Dn"), ("moved_1dn", "> 1 Dn")):
            bx.step(series["time_s"], series[key], where="post", label=label)
        bx.set_xlabel("run time (s)")
        bx.set_ylabel("units moved")
        bx.legend(fontsize=8)
        fig.tight_layout()
        fig.savefig(folder / "total_displacement.png", dpi=120)
        plt.close(fig)
        figures.append(("total_displacement.png", "Total displacement of all units against time (seed 000 Figs. 9, 12)"))

    s = summary.get("storm", {})
    if storm and len(storm.get("storm_time_s", [])):
        fig, (ax, bx) = plt.subplots(2, 1, figsize=(8, 6), sharex=True)
        ax.plot(storm["storm_time_s"], np.asarray(storm["pressure_Pa"]) / 1e3, color="tab:blue")
        ax.set_ylabel("pressure (kPa)")
        ax.set_title(f"storm input: voxel x = {s.get('voxel_x_m')} m, z = {s.get('voxel_z_m')} m (seed 000 Fig. 5)")
        bx.plot(storm["storm_time_s"], storm["eta_gauge_m"], color="tab:green")
        bx.set_ylabel(f"eta at x = {s.get('gauge_x_m')} m (m)")
        bx.set_xlabel("storm time (s)")
        fig.tight_layout()
        fig.savefig(folder / "storm.png", dpi=120)
        plt.close(fig)
        figures.append(("storm.png", "Storm input: pressure-time at the voxel and the free surface at the gauge"))

    # index.html
    def fmt(v, digits=4):
        if v is None:
            return "n/a"
        if isinstance(v, float):
            return f"{v:.{digits}g}"
        return html.escape(str(v))

    def table(rows, head=None):
        out = ["<table>"]
        if head:
            out.append("<tr>" + "".join(f"<th>{html.escape(h)}</th>" for h in head) + "</tr>")
        for r in rows:
            out.append("<tr>" + "".join(f"<td>{c}</td>" for c in r) + "</tr>")
        out.append("</table>")
        return "\n".join(out)

    d = summary.get("damage", {})
    p = summary.get("pack", {})
    des = summary.get("design", {})
    moved = d.get("moved_more_than_dn", {})
    damage_rows = [[f"units moved more than {k} Dn", fmt(v)] for k, v in moved.items()]
    damage_rows += [
        [f"rocking units (rotation above {fmt(d.get('rocking_angle_deg'))} deg)", fmt(d.get("rocking_units"))],
        [f"displaced units (more than {fmt(d.get('displaced_threshold_dn'))} Dn)", fmt(d.get("displaced_units"))],
        ["N<sub>od</sub> = n D<sub>n</sub> / B", f"{fmt(d.get('Nod'))} (B = {fmt(d.get('trunk_width_m'))} m)"],
        ["S = N<sub>od</sub> / (1 - p)", f"{fmt(d.get('S'))} (p = {fmt(d.get('porosity'))}, {fmt(d.get('porosity_source'))})"],
        ["&delta;<sub>rms</sub>", f"{fmt(d.get('delta_rms_m'))} m ({fmt(d.get('delta_rms_dn'))} Dn)"],
        ["mean / largest displacement", f"{fmt(d.get('mean_displacement_dn'))} / {fmt(d.get('max_displacement_dn'))} Dn "
                                        f"({fmt(d.get('max_displacement_unit'))})"],
        ["total displacement of all units", f"{fmt(d.get('total_displacement_m'))} m"],
        ["D, D<sub>z</sub>, D'<sub>z</sub> (seed 003, middle half)",
         f"{fmt(d.get('D_m'))}, {fmt(d.get('D_z_m'))}, {fmt(d.get('D_z_prime_m'))} m"],
    ]
    pack_rows = [
        [f"P2 ({fmt(p.get('axis'))} axis, mean director)", fmt(p.get("p2_before")), fmt(p.get("p2_after"))],
        ["P2 (Q tensor)", fmt(p.get("p2_q_before")), fmt(p.get("p2_q_after"))],
        ["porosity", fmt(p.get("porosity_before")), fmt(p.get("porosity_after"))],
    ]
    storm_rows = [
        ["file", fmt(s.get("file"))], ["title", fmt(s.get("title"))],
        ["records, storm times", f"{fmt(s.get('records'))}, {fmt(s.get('start_s'))} to {fmt(s.get('end_s'))} s"],
        ["time offset (storm time at run time 0)", f"{fmt(s.get('time_offset_s'))} s"],
        ["gauge", f"x = {fmt(s.get('gauge_x_m'))} m, {fmt(s.get('waves_at_gauge'))} waves"],
        ["H<sub>1/3</sub>, H<sub>max</sub>, H<sub>m0</sub>",
         f"{fmt(s.get('H1_3_m'))}, {fmt(s.get('Hmax_m'))}, {fmt(s.get('Hm0_m'))} m"],
        ["T<sub>m</sub> (zero crossing), T<sub>p</sub>", f"{fmt(s.get('Tm_s'))}, {fmt(s.get('Tp_s'))} s"],
        ["provenance H<sub>s</sub>, T<sub>p</sub>", f"{fmt(s.get('provenance_Hs_m'))} m, {fmt(s.get('provenance_Tp_s'))} s"],
        ["used: H<sub>s</sub>, T<sub>m</sub>, T<sub>p</sub>",
         f"{fmt(s.get('Hs_m'))} m ({fmt(s.get('Hs_source'))}), {fmt(s.get('Tm_used_s'))} s, {fmt(s.get('Tp_used_s'))} s"],
    ]
    design_rows = [
        ["unit, D<sub>n</sub>, density", f"{fmt(summary.get('unit_type'))}, {fmt(summary.get('dn_mean_m'))} m, "
                                         f"{fmt(summary.get('unit_density_kg_m3'))} kg/m<sup>3</sup>"],
        ["slope cot &alpha;", fmt(summary.get("slope_cot"))],
        ["&Delta;, N<sub>s</sub> = H<sub>s</sub> / (&Delta; D<sub>n</sub>)", f"{fmt(des.get('delta'))}, {fmt(des.get('Ns'))}"],
        ["s<sub>om</sub>, &xi;<sub>m</sub>, waves in the run",
         f"{fmt(des.get('s_om'))}, {fmt(des.get('xi_m'))}, {fmt(des.get('waves_in_run'))}"],
    ]
    formula_rows = []
    for f in des.get("formulas", []):
        values = ", ".join(f"{html.escape(k)} = {fmt(v)}" for k, v in f.get("values", {}).items())
        formula_rows.append([html.escape(f["name"]), "yes" if f.get("applicable") else "no", values,
                             html.escape(f.get("note", "")), html.escape(f.get("source", ""))])
    simulated = (f"simulated: S = {fmt(d.get('S'))}, N<sub>od</sub> = {fmt(d.get('Nod'))}, "
                 f"{fmt(d.get('displaced_units'))} of {fmt(summary.get('units'))} units displaced")
    run = a.run if a.run is not None else Path(summary.get("run", "."))
    stress_parts = stress_section(run, folder, figures, table, fmt)
    pvd = run / "bodies.pvd"
    if pvd.exists():
        write_paraview_state(folder / "paraview_state.py", pvd.resolve())
        pvd_link = (f'<a href="{html.escape(os.path.relpath(pvd, folder))}">bodies.pvd</a> '
                    "(open in ParaView: File &gt; Open; colour by <code>displacement</code>), or load "
                    "<a href='paraview_state.py'>paraview_state.py</a> (File &gt; Load State, Python state; or "
                    "<code>paraview --state=paraview_state.py</code>)")
    else:
        pvd_link = "no bodies.pvd in the run folder (output.vtk_interval was 0)"
    parts = [
        "<!DOCTYPE html><html><head><meta charset='utf-8'><title>armour damage report</title>",
        "<style>body{font-family:sans-serif;max-width:1000px;margin:auto}table{border-collapse:collapse;margin:1em 0}"
        "td,th{border:1px solid #aaa;padding:3px 8px;text-align:left;vertical-align:top}img{max-width:100%}</style>",
        "</head><body>",
        "<h1>Damage report</h1>",
        f"<p>run <code>{html.escape(str(summary.get('run')))}</code>, scene <code>{html.escape(str(summary.get('scene')))}"
        f"</code>; {fmt(summary.get('units'))} units; run time {fmt(summary.get('run_start_s'))} to "
        f"{fmt(summary.get('run_end_s'))} s ({fmt(summary.get('records'))} records). 3D animation: {pvd_link}.</p>",
        "<h2>Simulated damage</h2>", table(damage_rows),
        "<h2>Orientation order and porosity, before and after</h2>", table(pack_rows, ["", "before", "after"]),
        f"<p>{html.escape(p.get('note', '') or '')}</p>",
        "<h2>Storm input</h2>", table(storm_rows),
        "<h2>Design formulas beside the simulated damage</h2>", table(design_rows),
        f"<p>{simulated}</p>",
        table(formula_rows, ["formula", "applies", "prediction", "note", "source"]),
        "<p>Each formula is applied only within the range of the tests it was fitted to (docs/report.md); "
        "outside it the table says why it does not apply.</p>",
    ] + stress_parts + [
        "<h2>Figures</h2>",
    ]
    for name, caption in figures:
        parts.append(f"<figure><img src='{name}' alt='{html.escape(caption)}'><figcaption>{html.escape(caption)}"
                     "</figcaption></figure>")
    parts.append("<p>Tables: <a href='summary.json'>summary.json</a>, <a href='units.csv'>units.csv</a>, "
                 "<a href='timeseries.csv'>timeseries.csv</a>, <a href='storm.csv'>storm.csv</a>.</p>")
    parts.append("</body></html>")
    tmp = folder / f"index.html.tmp.{os.getpid()}"
    tmp.write_text("\n".join(parts))
    tmp.replace(folder / "index.html")
    print(f"figures: {', '.join(n for n, _ in figures)}; {folder / 'index.html'}")


if __name__ == "__main__":
    main()
