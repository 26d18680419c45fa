#!/usr/bin/env python3
"""CSV rows, Markdown tables and gnuplot plots for the bench studies (Python 3 standard library only;
plots need gnuplot, installed by bench/setup.sh).

  report.py append CSV STUDY --stats S.json [--rss-kb FILE] [--status S] [--error-stats E.json] [KEY=VALUE ...]
      add one run to CSV (header written when the file is new). STUDY picks the columns:
      convergence, knobs, scaling or ratio. Every number comes from the renderer's --stats JSON
      (render_seconds, spp, iterations, and relMSE / RMSE / mean bias of the `combined` layer
      against --reference) or from /usr/bin/time (max RSS); --error-stats: the relMSE of another
      render's --stats (scaling: the combination beside an RB timing).
  report.py convergence CSV OUTDIR [--no-plots]   -> OUTDIR/convergence.md, convergence-<scene>.png
  report.py knobs CSV OUTDIR [--no-plots]         -> OUTDIR/knobs.md, knobs-<knob>.png
  report.py scaling CSV OUTDIR                    -> OUTDIR/scaling.md
  report.py ratio CSV OUTDIR [--no-plots]         -> OUTDIR/ratio.md, ratio-<scene>-<W>x<H>.png
  report.py modes OUT DIR...                      -> OUT/modes.md: per scene and resolution, PT, RB and the
      default combination (--ratio auto) at the largest common budget, from each DIR's convergence.csv
      and ratio.csv (issue #12: the combination as good as the better estimator; auto within 1.25x)
  report.py check CSV STUDY [--min-rows N]        -> exit 1 unless the CSV is well formed
"""
import csv
import json
import math
import os
import shutil
import subprocess
import sys

COLUMNS = {
    "convergence": ["scene", "mode", "flags", "budget_s", "seed", "status", "render_seconds", "spp", "iterations",
                    "rel_mse", "rmse", "mean_bias", "triangles", "patches", "bins", "width", "height", "reference",
                    "reference_spp"],
    "knobs": ["knob", "value", "flags", "budget_s", "seed", "status", "render_seconds", "spp", "iterations",
              "rel_mse", "rmse", "mean_bias", "patches", "bins", "ratio", "width", "height", "reference",
              "reference_spp"],
    "ratio": ["scene", "setting", "flags", "budget_s", "seed", "status", "render_seconds", "probe_seconds", "ratio", "spp",
              "iterations", "rel_mse", "rmse", "mean_bias", "width", "height", "pt_seconds_per_spp",
              "rb_seconds_per_iteration", "reference", "reference_spp"],
    "scaling": ["series", "scene", "mode", "flags", "status", "triangles", "patches", "bins", "width", "height",
                "render_seconds", "spp", "iterations", "ms_per_sample", "ms_per_iteration", "fragments_per_iteration",
                "kernel_build_seconds", "load_seconds", "max_rss_mib", "device_mib", "bvh_build_seconds", "rel_mse",
                "patch_seconds", "pt_rel_mse", "combined_max_rss_mib"],
}
NUMERIC = {"budget_s", "render_seconds", "spp", "iterations", "rel_mse", "rmse", "mean_bias", "triangles", "patches",
           "bins", "width", "height", "reference_spp", "ms_per_sample", "ms_per_iteration", "fragments_per_iteration",
           "kernel_build_seconds", "load_seconds", "max_rss_mib", "device_mib", "ratio", "seed", "probe_seconds",
           "pt_seconds_per_spp", "rb_seconds_per_iteration", "bvh_build_seconds", "patch_seconds", "pt_rel_mse",
           "combined_max_rss_mib"}


def fnum(x):
    try:
        v = float(x)
        return v if math.isfinite(v) else None
    except (TypeError, ValueError):
        return None


def read_rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


# ----------------------------------------------------------------------------------------- append

def read_stats(path):
    """A renderer's --stats JSON, {} when there is none or it does not parse."""
    if not path or not os.path.exists(path):
        return {}
    try:
        with open(path) as f:
            return json.load(f)
    except (OSError, ValueError):
        return {}


def cmd_append(args):
    path, study = args[0], args[1]
    cols = COLUMNS[study]
    row = {c: "" for c in cols}
    stats_path = rss_path = error_stats_path = pt_error_stats_path = error_rss_path = None
    status = "ok"
    rest = args[2:]
    i = 0
    while i < len(rest):
        a = rest[i]
        if a == "--stats":
            stats_path = rest[i + 1]; i += 2
        elif a == "--rss-kb":
            rss_path = rest[i + 1]; i += 2
        elif a == "--error-stats":
            error_stats_path = rest[i + 1]; i += 2
        elif a == "--pt-error-stats":
            pt_error_stats_path = rest[i + 1]; i += 2
        elif a == "--error-rss-kb":
            error_rss_path = rest[i + 1]; i += 2
        elif a == "--status":
            status = rest[i + 1]; i += 2
        else:
            key, _, value = a.partition("=")
            if key not in row:
                sys.exit(f"report.py: unknown column {key!r} for {study}")
            row[key] = value
            i += 1
    s = read_stats(stats_path)
    if not s and status == "ok":
        status = "no-stats"
    row["status"] = status
    for key in ("render_seconds", "spp", "iterations", "triangles", "patches", "bins", "width", "height",
                "fragments_per_iteration", "kernel_build_seconds", "load_seconds", "bvh_build_seconds", "ratio",
                "patch_seconds"):
        if key in row and key in s and s[key] is not None:
            row[key] = s[key]
    for key in ("probe_seconds", "pt_seconds_per_spp", "rb_seconds_per_iteration"):  # --ratio auto's probe
        if key in row and s.get("ratio_auto", {}).get(key) is not None:
            row[key] = s["ratio_auto"][key]
    if s.get("interrupted"):
        row["status"] = "interrupted"
    layer = s.get("reference", {}).get("layers", {}).get("combined")
    if layer and "rel_mse" in row:
        row["rel_mse"], row["rmse"], row["mean_bias"] = layer["rel_mse"], layer["rmse"], layer["mean_bias"]
    if error_stats_path:
        layer = read_stats(error_stats_path).get("reference", {}).get("layers", {}).get("combined")
        if layer:
            row["rel_mse"] = layer["rel_mse"]
    if pt_error_stats_path:  # --mode pt's image is its "combined" layer
        layer = read_stats(pt_error_stats_path).get("reference", {}).get("layers", {}).get("combined")
        if layer:
            row["pt_rel_mse"] = layer["rel_mse"]
    secs = fnum(s.get("render_seconds"))
    if "ms_per_sample" in row and secs and fnum(s.get("spp")):
        row["ms_per_sample"] = 1e3 * secs / float(s["spp"])
    if "ms_per_iteration" in row and secs and fnum(s.get("iterations")):
        # includes the eye estimate and the warm-up iterations' share of the time (rb mode)
        row["ms_per_iteration"] = s.get("ms_per_iteration") or 1e3 * secs / float(s["iterations"])
    if "device_mib" in row and fnum(s.get("scene_device_bytes")):
        # the scene's buffers plus the ray-bundle pass's own estimate of what it allocates
        row["device_mib"] = (float(s["scene_device_bytes"]) + float(s.get("rb_device_bytes_estimate") or 0)) / 2**20
    for path_kb, key in ((rss_path, "max_rss_mib"), (error_rss_path, "combined_max_rss_mib")):
        if path_kb and key in row and os.path.exists(path_kb):
            with open(path_kb) as f:
                lines = [ln.strip() for ln in f if ln.strip().isdigit()]
            if lines:
                row[key] = int(lines[-1]) / 1024.0
    new = not os.path.exists(path) or os.path.getsize(path) == 0
    with open(path, "a", newline="") as f:
        w = csv.DictWriter(f, fieldnames=cols)
        if new:
            w.writeheader()
        w.writerow({k: (f"{v:.6g}" if isinstance(v, float) else v) for k, v in row.items()})


# ----------------------------------------------------------------------------------------- plots

def gnuplot_available():
    return shutil.which("gnuplot") is not None


def loglog_plot(png, title, series, ylabel="relMSE vs reference", xlabel="render time (s)", guide=True):
    """series: list of (label, [(x, y), ...]). Writes png, its data and the .gp script beside it.
    guide: a dashed 1/t line through the first series' first point (an unbiased estimator's slope)."""
    base = os.path.splitext(png)[0]
    data = base + ".dat"
    blocks, plots = [], []
    idx = 0
    for label, pts in series:
        pts = [(x, y) for x, y in pts if x and y and x > 0 and y > 0]
        if not pts:
            continue
        blocks.append(f"# {label}\n" + "\n".join(f"{x:.6g} {y:.6g}" for x, y in sorted(pts)) + "\n")
        plots.append(f"'{os.path.basename(data)}' index {idx} with linespoints lw 2 pt 7 title \"{label}\"")
        idx += 1
    with open(data, "w") as f:
        f.write("\n\n".join(blocks))
    first = next((sorted((x, y) for x, y in pts if x and y and x > 0 and y > 0) for _, pts in series
                  if any(x and y and x > 0 and y > 0 for x, y in pts)), None)
    if guide and first:
        x0, y0 = first[0]
        plots.append(f"{x0 * y0:.6g}/x with lines dt 2 lc rgb 'gray40' title \"∝ 1/t\"")
    term = "pngcairo size 900,600 font ',11'"
    script = f"""# regenerate: cd {os.path.dirname(os.path.abspath(png))} && gnuplot {os.path.basename(base)}.gp
set terminal {term}
set output '{os.path.basename(png)}'
set title "{title}" noenhanced
set logscale xy
set xlabel '{xlabel}'
set ylabel '{ylabel}'
set grid xtics ytics mxtics mytics
set key outside right top noenhanced
plot {", ".join(plots) if plots else "1/0 notitle"}
"""
    with open(base + ".gp", "w") as f:
        f.write(script)
    r = subprocess.run(["gnuplot", os.path.basename(base) + ".gp"], cwd=os.path.dirname(os.path.abspath(png)) or ".",
                       capture_output=True, text=True)
    if r.returncode != 0 and "pngcairo" in r.stderr:  # gnuplot without cairo: the libgd terminal
        with open(base + ".gp", "w") as f:
            f.write(script.replace(term, "png size 900,600"))
        r = subprocess.run(["gnuplot", os.path.basename(base) + ".gp"],
                           cwd=os.path.dirname(os.path.abspath(png)) or ".", capture_output=True, text=True)
    if r.returncode != 0 or not os.path.exists(png):
        sys.exit(f"report.py: gnuplot failed for {png}: {r.stderr.strip()}")


def fmt(x, spec):
    return "–" if x is None else format(x, spec)


# ----------------------------------------------------------------------------------------- convergence

def ok_rows(rows):
    return [r for r in rows if r["status"] == "ok" and fnum(r["rel_mse"]) and fnum(r["render_seconds"])]


def collapse(rows, keys):
    """Runs repeated with other seeds (same keys) -> one row each: the median relMSE (a single
    firefly can multiply one run's relMSE), the mean time, bias and RMSE, the median run's work."""
    groups = {}
    for r in rows:
        groups.setdefault(tuple(r[k] for k in keys), []).append(r)
    out = []
    for g in groups.values():
        g = sorted(g, key=lambda r: float(r["rel_mse"]))
        mid = dict(g[len(g) // 2])
        if len(g) % 2 == 0:
            mid["rel_mse"] = 0.5 * (float(g[len(g) // 2 - 1]["rel_mse"]) + float(g[len(g) // 2]["rel_mse"]))
        for k in ("render_seconds", "mean_bias", "rmse", "probe_seconds"):
            vals = [fnum(r.get(k)) for r in g if fnum(r.get(k)) is not None]
            if vals:
                mid[k] = sum(vals) / len(vals)
        mid["runs"] = len(g)
        out.append(mid)
    return out


def efficiency(r):
    return 1.0 / (float(r["rel_mse"]) * float(r["render_seconds"]))


def size_of(r):
    return f"{r['width']}x{r['height']}"


def cmd_convergence(args):
    path, out = args[0], args[1]
    plots = "--no-plots" not in args
    rows = read_rows(path)
    good = collapse(ok_rows(rows), ("scene", "width", "height", "mode", "budget_s"))
    runs = max((r["runs"] for r in good), default=1)
    scenes = list(dict.fromkeys(r["scene"] for r in rows))
    modes = list(dict.fromkeys(r["mode"] for r in rows))
    budgets = sorted({float(r["budget_s"]) for r in rows})
    md = []
    md.append("<!-- generated by bench/convergence.sh from convergence.csv; do not edit by hand -->")
    md.append("Efficiency `1/(relMSE·t)` of each mode relative to `--mode pt` at the same wall-time budget "
              "(t = the renderer's `render_seconds`, so kernel build, scene load and the `--ratio auto` probe of the "
              "combined modes are not counted — `ratio.md` counts the probe; "
              "> 1 means the mode buys more accuracy per second than the path tracer). "
              "relMSE and mean bias are at the largest budget." +
              (f" Each point is the median relMSE of {runs} runs with independent seeds." if runs > 1 else
               " Each point is one run (`--repeats N` takes the median of N)."))
    md.append("")
    head = "| scene | mode | " + " | ".join(f"{b:g} s" for b in budgets) + " | relMSE | mean bias | work done |"
    # One section per scene and resolution; the first resolution's plots keep the plain name.
    sizes = list(dict.fromkeys(size_of(r) for r in good)) or [""]
    for scene, size in ((scene, size) for scene in scenes for size in sizes):
        srows = [r for r in good if r["scene"] == scene and size_of(r) == size]
        if not srows:
            md.append(f"*{scene} {size}: no successful runs*\n")
            continue
        plot_name = f"convergence-{scene}" + ("" if size == sizes[0] else f"-{size}")
        any_row = srows[0]
        md.append(f"**{scene}** ({any_row['triangles']} triangles, {any_row['width']}×{any_row['height']}, "
                  f"reference {any_row['reference_spp']} spp)")
        md.append("")
        md.append(head)
        md.append("|---|---|" + "---|" * len(budgets) + "---|---|---|")
        pt_eff = {float(r["budget_s"]): efficiency(r) for r in srows if r["mode"] == "pt"}
        for mode in modes:
            mrows = {float(r["budget_s"]): r for r in srows if r["mode"] == mode}
            failed = [r for r in rows if r["scene"] == scene and r["mode"] == mode and r["status"] != "ok"]
            if not mrows:
                reason = failed[0]["status"] if failed else "not run"
                md.append(f"| {scene} | {mode} | " + " | ".join("–" for _ in budgets) + f" | – | – | {reason} |")
                continue
            cells = []
            for b in budgets:
                r = mrows.get(b)
                cells.append(fmt(efficiency(r) / pt_eff[b], ".2f") if r and b in pt_eff else "–")
            last = mrows[max(mrows)]
            work = f"{last['spp'] or 0} spp" + (f" + {last['iterations']} it" if last["iterations"] not in ("", "0") else "")
            md.append(f"| {scene} | {mode} | " + " | ".join(cells) +
                      f" | {fmt(fnum(last['rel_mse']), '.4g')} | {fmt(fnum(last['mean_bias']), '+.4f')} | {work} |")
        top = max(float(r["budget_s"]) for r in srows)
        at_top = [r for r in srows if float(r["budget_s"]) == top]
        if top in pt_eff and at_top:
            best = max(at_top, key=efficiency)
            md.append("")
            md.append(f"Most efficient at {top:g} s on {scene} at {size}: `{best['mode']}` "
                      f"({efficiency(best) / pt_eff[top]:.2f}× PT).")
        # The reference's own noise: a PT image of n spp against a reference of N spp measures about
        # c (1/n + 1/N), so the reference's share of every relMSE is about relMSE_PT * n / (n + N).
        floors = [float(r["rel_mse"]) * float(r["spp"]) / (float(r["spp"]) + float(r["reference_spp"]))
                  for r in srows if r["mode"] == "pt" and fnum(r["spp"]) and fnum(r["reference_spp"])]
        if floors:
            md.append("")
            md.append(f"Reference noise floor (the reference's own share of relMSE, from the PT rows as relMSE·n/(n + N) "
                      f"for n spp against the reference's N): "
                      f"≈ {sorted(floors)[len(floors) // 2]:.2g}; relMSE values near it are limited by the reference.")
        md.append("")
        if plots:
            series = []
            for mode in modes:
                pts = [(float(r["render_seconds"]), float(r["rel_mse"])) for r in srows if r["mode"] == mode]
                series.append((mode, pts))
            png = os.path.join(out, f"{plot_name}.png")
            loglog_plot(png, f"{scene} at {size}: relMSE vs render time", series)
            md.append(f"![relMSE vs time, {scene} at {size}]({plot_name}.png)")
            md.append("")
    failed = [r for r in rows if r["status"] != "ok"]
    if failed:
        md.append(f"{len(failed)} run(s) did not finish: " +
                  ", ".join(f"{r['scene']}/{r['mode']}@{r['budget_s']}s ({r['status']})" for r in failed[:12]))
        md.append("")
    with open(os.path.join(out, "convergence.md"), "w") as f:
        f.write("\n".join(md))


# ----------------------------------------------------------------------------------------- knobs

def cmd_knobs(args):
    path, out = args[0], args[1]
    plots = "--no-plots" not in args
    rows = read_rows(path)
    good = collapse(ok_rows(rows), ("knob", "value", "budget_s"))
    knobs = list(dict.fromkeys(r["knob"] for r in rows))
    budgets = sorted({float(r["budget_s"]) for r in rows})
    md = ["<!-- generated by bench/knobs.sh from knobs.csv; do not edit by hand -->"]
    for knob in knobs:
        krows = [r for r in good if r["knob"] == knob]
        values = list(dict.fromkeys(r["value"] for r in rows if r["knob"] == knob))
        any_row = krows[0] if krows else None
        where = f" ({any_row['width']}×{any_row['height']}, reference {any_row['reference_spp']} spp)" if any_row else ""
        md.append(f"**`{knob}`**{where}: relMSE at each wall-time budget; efficiency `1/(relMSE·t)` at the "
                  f"largest budget relative to the renderer's default (the row marked *default*).")
        md.append("")
        md.append(f"| {knob} | patches | bins | " + " | ".join(f"relMSE {b:g} s" for b in budgets) +
                  " | mean bias | efficiency vs default |")
        md.append("|---|---|---|" + "---|" * len(budgets) + "---|---|")
        top = max(budgets) if budgets else None
        default = [r for r in krows if r["value"] == "default" and float(r["budget_s"]) == top]
        base = efficiency(default[0]) if default else None
        best = None
        for v in values:
            vrows = {float(r["budget_s"]): r for r in krows if r["value"] == v}
            if not vrows:
                status = next((r["status"] for r in rows if r["knob"] == knob and r["value"] == v), "not run")
                md.append(f"| {v} | – | – | " + " | ".join("–" for _ in budgets) + f" | – | {status} |")
                continue
            last = vrows[max(vrows)]
            rel = efficiency(last) / base if base and top in vrows else None
            if rel is not None and (best is None or rel > best[1]):
                best = (v, rel)
            md.append(f"| {'*default*' if v == 'default' else v} | {last['patches']} | {last['bins']} | " +
                      " | ".join(fmt(fnum(vrows[b]["rel_mse"]) if b in vrows else None, ".4g") for b in budgets) +
                      f" | {fmt(fnum(last['mean_bias']), '+.4f')} | {fmt(rel, '.2f')} |")
        if best:
            md.append("")
            md.append(f"Most efficient at {top:g} s: `{knob} {best[0]}` ({best[1]:.2f}× the default).")
        md.append("")
        if plots and krows:
            series = [(f"{knob} {v}", [(float(r["render_seconds"]), float(r["rel_mse"]))
                                       for r in krows if r["value"] == v]) for v in values]
            name = knob.lstrip("-")
            loglog_plot(os.path.join(out, f"knobs-{name}.png"), f"cornell-glossy, combined product: {knob}", series)
            md.append(f"![relMSE vs time for {knob}](knobs-{name}.png)")
            md.append("")
    with open(os.path.join(out, "knobs.md"), "w") as f:
        f.write("\n".join(md))


# ----------------------------------------------------------------------------------------- ratio

AUTO_TOLERANCE = 1.25  # issue #12: --ratio auto within 1.25x of the best fixed ratio's efficiency


def ratio_efficiency(r):
    """1/(relMSE·t), t = render time plus the probe's (auto throws the probe's work away)."""
    return 1.0 / (float(r["rel_mse"]) * (float(r["render_seconds"]) + (fnum(r.get("probe_seconds")) or 0.0)))


def ratio_num(x):
    """c from the stats: a number, or "inf" where --ratio auto chose the path tracer alone."""
    try:
        v = float(x)
        return v if v > 0 else None
    except (TypeError, ValueError):
        return None


def ratio_text(c):
    if c is None:
        return "–"
    if math.isinf(c):
        return "∞ (PT alone)"
    return f"{c:g}" if c >= 1 else f"1/{1 / c:g}"


def cmd_ratio(args):
    path, out = args[0], args[1]
    plots = "--no-plots" not in args
    rows = read_rows(path)
    good = collapse(ok_rows(rows), ("scene", "width", "height", "setting", "budget_s"))
    runs = max((r["runs"] for r in good), default=1)
    scenes = list(dict.fromkeys(r["scene"] for r in rows))
    settings = list(dict.fromkeys(r["setting"] for r in rows))
    budgets = sorted({float(r["budget_s"]) for r in rows})
    sizes = list(dict.fromkeys(size_of(r) for r in good))
    md = ["<!-- generated by bench/ratio.sh from ratio.csv; do not edit by hand -->",
          "`--mode combined --weights product` at fixed ratios and at `--ratio auto`. Efficiency: the geometric "
          "mean over the budgets of `1/(relMSE·t)`, t = `render_seconds` (plus `probe_seconds` for auto, whose "
          "probe work is discarded); *vs best* is a setting's efficiency over the best fixed ratio's." +
          (f" Each point is the median relMSE of {runs} runs." if runs > 1 else " Each point is one run."), ""]
    summary = []
    for scene in scenes:
        for size in sizes:
            srows = [r for r in good if r["scene"] == scene and size_of(r) == size]
            if not srows:
                continue
            eff, used = {}, {}
            for setting in settings:
                pts = {float(r["budget_s"]): r for r in srows if r["setting"] == setting}
                if pts and all(b in pts for b in budgets):
                    eff[setting] = math.exp(sum(math.log(ratio_efficiency(pts[b])) for b in budgets) / len(budgets))
                used[setting] = sorted({ratio_num(r["ratio"]) for r in pts.values() if ratio_num(r["ratio"])}, reverse=True)
            fixed = {k: v for k, v in eff.items() if k != "auto"}
            best = max(fixed, key=fixed.get) if fixed else None
            md.append(f"**{scene}** at {size} (reference {srows[0]['reference_spp']} spp)")
            md.append("")
            md.append("| --ratio | c used | " + " | ".join(f"relMSE {b:g} s" for b in budgets) +
                      " | work at the largest budget | efficiency | vs best |")
            md.append("|---|---|" + "---|" * len(budgets) + "---|---|---|")
            for setting in settings:
                pts = {float(r["budget_s"]): r for r in srows if r["setting"] == setting}
                if not pts:
                    status = next((r["status"] for r in rows if r["scene"] == scene and r["setting"] == setting
                                   and r["status"] != "ok"), "not run")
                    md.append(f"| {setting} | – | " + " | ".join("–" for _ in budgets) + f" | {status} | – | – |")
                    continue
                last = pts[max(pts)]
                work = f"{last['spp'] or 0} spp + {last['iterations'] or 0} it"
                e = eff.get(setting)
                rel = e / fixed[best] if e and best else None
                md.append(f"| {'**' + setting + '**' if setting == best else setting} | "
                          f"{', '.join(ratio_text(c) for c in used[setting]) or '–'} | " +
                          " | ".join(fmt(fnum(pts[b]["rel_mse"]) if b in pts else None, ".4g") for b in budgets) +
                          f" | {work} | {fmt(e, '.4g')} | {fmt(rel, '.2f')} |")
            md.append("")
            if plots:
                series = [(f"--ratio {k}", [(float(r["render_seconds"]) + (fnum(r.get("probe_seconds")) or 0.0),
                                             float(r["rel_mse"])) for r in srows if r["setting"] == k])
                          for k in settings]
                name = f"ratio-{scene}-{size}"
                loglog_plot(os.path.join(out, name + ".png"), f"{scene} at {size}: combined, product weights", series)
                md.append(f"![relMSE vs time per ratio, {scene} at {size}]({name}.png)")
                md.append("")
            a = eff.get("auto")
            # The PT time share f at which auto's rule (passes/combined.cpp) gives the best fixed ratio,
            # from the probe's measured costs: f = c t_PT / (c t_PT + t_RB).
            t_pt = [fnum(r["pt_seconds_per_spp"]) for r in srows if fnum(r.get("pt_seconds_per_spp"))]
            t_rb = [fnum(r["rb_seconds_per_iteration"]) for r in srows if fnum(r.get("rb_seconds_per_iteration"))]
            share = None
            if best and t_pt and t_rb:
                c, tp, tr = fnum(used[best][0]) if used.get(best) else None, sorted(t_pt)[len(t_pt) // 2], sorted(t_rb)[len(t_rb) // 2]
                share = c * tp / (c * tp + tr) if c else None
            summary.append((scene, size, best, fixed.get(best), used.get("auto", []), a,
                            fixed[best] / a if a and best else None, share))
    if summary:
        md.append(f"`--ratio auto` against the best fixed ratio (requirement: best / auto ≤ {AUTO_TOLERANCE}):")
        md.append("")
        md.append("| scene | resolution | best fixed ratio | its efficiency | auto chose | auto's efficiency | "
                  "best / auto | within 1.25× | PT time share at the best ratio |")
        md.append("|---|---|---|---|---|---|---|---|---|")
        for scene, size, best, be, chose, a, q, share in summary:
            verdict = "–" if q is None else ("yes" if q <= AUTO_TOLERANCE else "**no**")
            md.append(f"| {scene} | {size} | {best or '–'} | {fmt(be, '.4g')} | "
                      f"{', '.join(ratio_text(c) for c in chose) or '–'} | {fmt(a, '.4g')} | {fmt(q, '.2f')} | {verdict} | "
                      f"{fmt(share, '.2f')} |")
        md.append("")
        shares = sorted(x[7] for x in summary if x[7] is not None)
        if shares:
            md.append(f"The last column is the PT time share (`kAutoRatioPtTimeShareEyeShared` / `...EyePt`, passes/combined.h) at which `--ratio auto` "
                      f"would have picked each scene's best fixed ratio, from the probe's measured costs; median "
                      f"{shares[len(shares) // 2]:.2f}, range {shares[0]:.2f}–{shares[-1]:.2f}.")
            md.append("")
    failed = [r for r in rows if r["status"] != "ok"]
    if failed:
        md.append(f"{len(failed)} run(s) did not finish: " +
                  ", ".join(f"{r['scene']}/{r['setting']}@{r['budget_s']}s ({r['status']})" for r in failed[:12]))
        md.append("")
    with open(os.path.join(out, "ratio.md"), "w") as f:
        f.write("\n".join(md))


# ----------------------------------------------------------------------------------------- scaling

def house_table(series, rows):
    """The fixed-rooms house (bench/scaling.sh): one house at several triangle counts, so RB's cost
    per iteration and the peak memory against the first row show what the triangles alone cost
    (the issue's bounds: at most 1.5x from 100 k to 1 M triangles, at most 1.5 GB at 1 M)."""
    md = [f"**{series}**", "",
          "| scene | triangles | load s | BVH build s | patch layout s | patches | ms / RB iteration | × first row | "
          "peak host MiB (RB) | relMSE combined | relMSE PT | combined / PT | peak host MiB (combined) |",
          "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    first = None
    for r in rows:
        if r["status"] != "ok":
            md.append(f"| {r['scene']} | {r['triangles'] or '–'} | {r['status']} |" + " |" * 10)
            continue
        ms_i = fnum(r["ms_per_iteration"])
        first = first or ms_i
        combined, pt = fnum(r.get("rel_mse")), fnum(r.get("pt_rel_mse"))
        md.append(f"| {r['scene']} | {r['triangles']} | {fmt(fnum(r['load_seconds']), '.3g')} | "
                  f"{fmt(fnum(r.get('bvh_build_seconds')), '.3g')} | {fmt(fnum(r.get('patch_seconds')), '.3g')} | "
                  f"{r['patches']} | {fmt(ms_i, '.3g')} | "
                  f"{fmt(ms_i / first if ms_i and first else None, '.2f')} | {fmt(fnum(r['max_rss_mib']), '.0f')} | "
                  f"{fmt(combined, '.3g')} | {fmt(pt, '.3g')} | {fmt(combined / pt if combined and pt else None, '.2f')} | "
                  f"{fmt(fnum(r.get('combined_max_rss_mib')), '.0f')} |")
    md += ["", f"RB: `{rows[0]['flags']}`, ms per iteration as `--stats` gives it (warm-up included). "
           "Load, BVH build and patch layout (clusters included): `--stats`' `load_seconds`, `bvh_build_seconds` "
           "and `patch_seconds`. The relMSE columns (`scaling.sh --house-error`): `--mode combined` at its "
           "defaults and `--mode pt`, 30 s each, against one path-traced reference of the first row's house "
           "(1024 spp at 640×360): every row is the same surfaces and lights, so the same image.", ""]
    return md


def cmd_scaling(args):
    path, out = args[0], args[1]
    rows = read_rows(path)
    md = ["<!-- generated by bench/scaling.sh from scaling.csv; do not edit by hand -->",
          "Time per PT sample is for the whole image (ms per spp); time per RB iteration is `--mode rb`'s "
          "`ms_per_iteration` (binning, exchange, gather and the eye estimate). Peak host memory is "
          "`/usr/bin/time -v`'s maximum resident set of the whole process (on the PoCL CPU device the "
          "device buffers live in host memory, so it includes them). Device MiB: the scene's buffers "
          "(`scene_device_bytes`) plus the ray-bundle pass's estimate of its own (`rb_device_bytes_estimate`).",
          ""]
    has_dev = any(fnum(r.get("device_mib")) for r in rows)
    for series in dict.fromkeys(r["series"] for r in rows):
        srows = [r for r in rows if r["series"] == series]
        if series.startswith("house at fixed rooms"):
            md += house_table(series, srows)
            continue
        md.append(f"**{series}**")
        md.append("")
        md.append("| scene | mode | triangles | patches | bins | pixels | ms / PT sample | ms / RB iteration | "
                  "fragments / iteration | M fragments / s | peak host MiB |" + (" device MiB |" if has_dev else ""))
        md.append("|---|---|---|---|---|---|---|---|---|---|---|" + ("---|" if has_dev else ""))
        for r in srows:
            if r["status"] != "ok":
                md.append(f"| {r['scene']} | {r['mode']} {r['flags']} | {r['triangles'] or '–'} | {r['patches'] or '–'} | "
                          f"{r['bins'] or '–'} | {r['width']}×{r['height']} | {r['status']} | | | | |" +
                          (" |" if has_dev else ""))
                continue
            pixels = f"{r['width']}×{r['height']}"
            ms_s = fnum(r["ms_per_sample"]) if r["mode"] != "rb" else None
            ms_i = fnum(r["ms_per_iteration"]) if r["mode"] == "rb" else None
            frag = fnum(r["fragments_per_iteration"]) if r["mode"] == "rb" else None
            frag_rate = frag / ms_i * 1e-3 if frag and ms_i else None
            md.append(f"| {r['scene']} | {r['mode']} | {r['triangles']} | {r['patches']} | {r['bins'] or '–'} | {pixels} | "
                      f"{fmt(ms_s, '.3g')} | {fmt(ms_i, '.3g')} | {fmt(frag, '.3g')} | {fmt(frag_rate, '.3g')} | "
                      f"{fmt(fnum(r['max_rss_mib']), '.0f')} |" +
                      (f" {fmt(fnum(r['device_mib']), '.0f')} |" if has_dev else ""))
        md.append("")
    if not has_dev:
        md.append("Device memory: this renderer's `--stats` does not report it (column left out).")
        md.append("")
    with open(os.path.join(out, "scaling.md"), "w") as f:
        f.write("\n".join(md))


# ----------------------------------------------------------------------------------------- check

def cmd_check(args):
    path, study = args[0], args[1]
    min_rows = int(args[args.index("--min-rows") + 1]) if "--min-rows" in args else 1
    errors = []
    with open(path, newline="") as f:
        reader = csv.reader(f)
        header = next(reader, None)
        if header != COLUMNS[study]:
            errors.append(f"header {header} != {COLUMNS[study]}")
        rows = list(reader)
    if len(rows) < min_rows:
        errors.append(f"{len(rows)} rows, expected at least {min_rows}")
    ok = 0
    for n, r in enumerate(rows, 2):
        if header and len(r) != len(header):
            errors.append(f"line {n}: {len(r)} fields, expected {len(header)}")
            continue
        d = dict(zip(COLUMNS[study], r))
        for k, v in d.items():
            if k in NUMERIC and v != "" and fnum(v) is None and not (k == "ratio" and ratio_num(v)):  # "inf": PT alone
                errors.append(f"line {n}: {k}={v!r} is not a finite number")
        if d.get("status") == "ok":
            ok += 1
            need = ["render_seconds"] + (["rel_mse", "rmse", "mean_bias"] if study != "scaling" else [])
            for k in need:
                if fnum(d.get(k)) is None:
                    errors.append(f"line {n}: status ok but {k} is empty")
    if ok == 0:
        errors.append("no run finished with status ok")
    for e in errors[:20]:
        print(f"{path}: {e}", file=sys.stderr)
    if errors:
        sys.exit(1)
    print(f"{path}: {len(rows)} rows, {ok} ok")


# ----------------------------------------------------------------------------------------- modes

def median(values):
    if not values:
        return None
    v, n = sorted(values), len(values)
    return v[n // 2] if n % 2 else 0.5 * (v[n // 2 - 1] + v[n // 2])


def cmd_modes(args):
    """The default-mode check of issue #12 over the sweeps in DIRs (bench/sweep.sh writes one per
    resolution): at the largest budget both studies ran, the relMSE of PT, RB and the combination at
    its defaults (the convergence study's combined-product row and the ratio sweep's auto row are two
    runs of the same command: their median), and auto's efficiency over the best fixed ratio's."""
    out, dirs = args[0], args[1:]
    conv, ratio = [], []
    for d in dirs:
        for name, rows in (("convergence.csv", conv), ("ratio.csv", ratio)):
            p = os.path.join(d, name)
            if os.path.exists(p):
                rows.extend(ok_rows(read_rows(p)))
    md = ["<!-- generated by bench/report.py modes; do not edit by hand -->",
          "At the largest budget of the sweep (`bench/sweep.sh`): relMSE of `--mode pt`, `--mode rb` and "
          "`--mode combined` at its defaults (`--ratio auto`, `--eye-direct auto`; the median of the convergence "
          "study's run and the ratio sweep's, two seeds), and the combination's relMSE over the better "
          "estimator's (≤ 1: at least as good; issue #12 makes combined the default when it is everywhere). "
          "*auto / best fixed*: efficiency of `--ratio auto` (probe counted) over the best fixed ratio's "
          "(requirement ≥ 0.8, i.e. best / auto ≤ 1.25).", "",
          "| scene | resolution | budget | PT | RB | combined (defaults) | combined / better | c chosen | "
          "auto / best fixed |",
          "|---|---|---|---|---|---|---|---|---|"]
    keys = list(dict.fromkeys((r["scene"], size_of(r)) for r in conv))
    verdicts, within, autos = [], [], []
    for scene, size in keys:
        c_rows = [r for r in conv if r["scene"] == scene and size_of(r) == size]
        r_rows = [r for r in ratio if r["scene"] == scene and size_of(r) == size]
        budget = max(float(r["budget_s"]) for r in c_rows)
        at = lambda rows, key, val: [float(r["rel_mse"]) for r in rows
                                     if r[key] == val and float(r["budget_s"]) == budget]
        pt, rb = at(c_rows, "mode", "pt"), at(c_rows, "mode", "rb")
        comb = at(c_rows, "mode", "combined-product") + at(r_rows, "setting", "auto")
        pt, rb, comb = median(pt), median(rb), median(comb)
        better = min(x for x in (pt, rb) if x is not None) if (pt or rb) else None
        q = comb / better if comb and better else None
        chosen = sorted({ratio_num(r["ratio"]) for r in r_rows if r["setting"] == "auto" and ratio_num(r.get("ratio"))})
        eff = {}
        for r in r_rows:
            if float(r["budget_s"]) == budget:
                eff.setdefault(r["setting"], []).append(ratio_efficiency(r))
        fixed = {k: max(v) for k, v in eff.items() if k != "auto"}
        a = max(eff["auto"]) if "auto" in eff else None
        auto_q = a / max(fixed.values()) if a and fixed else None
        verdicts.append(q is not None and q <= 1.0)
        within.append(q is not None and q <= 1.25)
        if auto_q is not None:
            autos.append(auto_q >= 0.8)
        md.append(f"| {scene} | {size} | {budget:g} s | {fmt(pt, '.3g')} | {fmt(rb, '.3g')} | {fmt(comb, '.3g')} | "
                  f"{fmt(q, '.2f')}{'' if q is None or q <= 1.0 else ' **(worse)**'} | "
                  f"{', '.join(ratio_text(c) for c in chosen) or '–'} | {fmt(auto_q, '.2f')} |")
    md.append("")
    md.append(f"The combination is at least as good as the better estimator in {sum(verdicts)} of {len(verdicts)} "
              f"scene-resolution pairs, and within 0.8x of its efficiency (combined / better ≤ 1.25, issue #12) in "
              f"{sum(w for w in within)} of {len(within)}; auto within 1.25x of the best fixed ratio in "
              f"{sum(a for a in autos)} of {len(autos)}.")
    os.makedirs(out, exist_ok=True)
    with open(os.path.join(out, "modes.md"), "w") as f:
        f.write("\n".join(md) + "\n")
    print("\n".join(md))


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    cmd, args = sys.argv[1], sys.argv[2:]
    if cmd in ("convergence", "knobs", "scaling", "ratio"):
        os.makedirs(args[1], exist_ok=True)
    {"append": cmd_append, "convergence": cmd_convergence, "knobs": cmd_knobs, "scaling": cmd_scaling,
     "check": cmd_check, "ratio": cmd_ratio, "modes": cmd_modes}[cmd](args)


if __name__ == "__main__":
    main()
