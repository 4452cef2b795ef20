#!/usr/bin/env python3
"""Draws obscura_report's error-against-run-time charts from results.json.

usage: plot_report.py results.json error_vs_time.png

Each chart is log-log, x = time per frame in ms, y = the error, both the mean over the
report's scenes; one curve per method + device through the quality presets (colour: the
method; line style: the device), and the ray tracer's own curve through its ray counts.
Writes, next to error_vs_time.png:
  error_vs_time.png            AO: the methods at their defaults (no variants), RMSE
  error_vs_time_by_scene.png   the same per scene
  error_vs_time_hbao.png       AO of HBAO and its variants
  error_vs_time_variants.png   AO of the other methods' variants, one panel per method
  error_vs_time_do.png         DO (quantity "do"): relative RMSE against Reference.DO
  error_vs_time_gi.png         GI (quantity "gi"): relative RMSE against Reference.GI (within r_max)
The DO and GI charts appear when the rows hold those quantities.
"""
import json
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

RAYTRACE = "raytrace"


def curves(rows, preset_order, metric="rmse"):
    """{(method, device): [(label, time_ms, error), ...]} in preset / ray-count order."""
    out = {}
    for r in rows:
        key = (r["method"], r["device"])
        if r["method"] == RAYTRACE:
            key = (RAYTRACE, r["device"], r.get("definition", ""))
        out.setdefault(key, []).append(r)
    result = {}
    for key, group in out.items():
        if key[0] == RAYTRACE:
            group.sort(key=lambda r: r["rays"])
            labels = [f'{r["rays"]} ray' + ("s" if r["rays"] != 1 else "") for r in group]
        else:
            group.sort(key=lambda r: preset_order.index(r["preset"]) if r["preset"] in preset_order else 99)
            labels = [r["preset"] for r in group]
        result[key] = [(lab, r["time_ms"], r[metric]) for lab, r in zip(labels, group)]
    return result


def mean_curves(rows, preset_order, scenes, metric="rmse"):
    """Per (method, device) and point label: mean time and mean error over the scenes."""
    per_scene = [curves([r for r in rows if r["scene"] == s], preset_order, metric) for s in scenes]
    merged = {}
    for c in per_scene:
        for key, points in c.items():
            for lab, t, e in points:
                merged.setdefault(key, {}).setdefault(lab, []).append((t, e))
    result = {}
    for key, by_label in merged.items():
        # keep the order of the first scene that has this curve
        order = next(c[key] for c in per_scene if key in c)
        pts = []
        for lab, _, _ in order:
            vals = by_label[lab]
            pts.append((lab, sum(v[0] for v in vals) / len(vals), sum(v[1] for v in vals) / len(vals)))
        result[key] = pts
    return result


DEVICE_STYLES = {"cpu": "-", "gl-osmesa": "--", "gl-egl": ":"}


def draw(ax, curve_map, title, label_points=True, ylabel="RMSE vs converged reference", label_only=None):
    """Colour = method, line style = device; the ray tracer's curves in black. Points are labelled with
    their preset (for `label_only`'s method alone when given), above and below the line by turns."""
    colours = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    markers = "osD^v<>p"
    methods = sorted({k[0] for k in curve_map if k[0] != RAYTRACE})
    labelled = set()  # methods whose presets are labelled (devices share sample counts, so one curve each)
    traced = sorted(k for k in curve_map if k[0] == RAYTRACE)
    obscura_keys = sorted((k for k in curve_map if k[0] != RAYTRACE), key=lambda k: (methods.index(k[0]), k[1]))
    for key in obscura_keys + traced:
        pts = [p for p in curve_map[key] if p[1] > 0 and p[2] > 0]
        if not pts:
            continue
        xs, ys = [p[1] for p in pts], [p[2] for p in pts]
        if key[0] == RAYTRACE:
            style = "k--x" if traced.index(key) == 0 else "k:+"
            ax.plot(xs, ys, style, lw=1.2, ms=6, label=f"ray traced ({key[2]})" if key[2] else "ray traced")
        else:
            m = methods.index(key[0])
            ax.plot(xs, ys, DEVICE_STYLES.get(key[1], "-."), marker=markers[m % len(markers)],
                    color=colours[m % len(colours)], lw=1.5, ms=5, label=f"{key[0]} on {key[1]}")
        wanted = label_only is None or key[0] in (label_only, RAYTRACE)
        if label_points and wanted and key[:1] + key[2:] not in labelled:
            labelled.add(key[:1] + key[2:])
            below = key[0] != RAYTRACE and methods.index(key[0]) % 2 == 1
            for lab, x, y in pts:
                ax.annotate(lab, (x, y), textcoords="offset points", xytext=(4, -10 if below else 3), fontsize=7)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("time per frame (ms)")
    ax.set_ylabel(ylabel)
    ax.set_title(title, fontsize=10)
    ax.grid(True, which="both", lw=0.3, alpha=0.6)


def family(method):
    """The method a variant belongs to: "hbao+open" -> "hbao", "discs-sum" -> "discs", "ssdo-noint" -> "ssdo"."""
    for sep in "+-":
        method = method.split(sep)[0]
    return method


def is_variant(method):
    return method != RAYTRACE and family(method) != method


def single_chart(path, curve_map, title, ylabel, label_only=None):
    fig, ax = plt.subplots(figsize=(8, 6), dpi=120)
    draw(ax, curve_map, title, ylabel=ylabel, label_only=label_only)
    ax.legend(fontsize=8, loc="best")
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)


def family_rows(rows, fam, definition):
    """The rows of a method and its variants, with the ray tracer's curve of their AO definition."""
    ray_def = "cosine_linear" if fam == "ssdo" else definition
    return [r for r in rows if family(r["method"]) == fam or (r["method"] == RAYTRACE and r["definition"] == ray_def)]


def variants_charts(stem, ext, rows, order, scenes, definition):
    """HBAO's variants on their own chart; the other methods' variants one panel each, two columns."""
    written = []
    families = sorted({family(r["method"]) for r in rows if is_variant(r["method"])})
    if "hbao" in families:
        path = f"{stem}_hbao{ext}"
        single_chart(path, mean_curves(family_rows(rows, "hbao", definition), order, scenes),
                     "HBAO and its variants: AO error against time", "RMSE vs converged reference", "hbao")
        written.append(path)
    others = [f for f in families if f != "hbao"]
    if others:
        cols = min(2, len(others))
        nrows = math.ceil(len(others) / cols)
        fig, axes = plt.subplots(nrows, cols, figsize=(7.5 * cols, 5.5 * nrows), dpi=100, squeeze=False)
        for i, fam in enumerate(others):
            ax = axes[i // cols][i % cols]
            draw(ax, mean_curves(family_rows(rows, fam, definition), order, scenes), f"{fam} and its variants (AO)",
                 label_only=fam)
            ax.legend(fontsize=8, loc="best")
        for j in range(len(others), nrows * cols):
            axes[j // cols][j % cols].axis("off")
        fig.tight_layout()
        path = f"{stem}_variants{ext}"
        fig.savefig(path)
        plt.close(fig)
        written.append(path)
    return written


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    with open(sys.argv[1]) as f:
        data = json.load(f)
    meta, rows = data["meta"], data["rows"]
    rows = [r for r in rows if r.get("rmse") is not None and math.isfinite(r["rmse"])]
    by_quantity = {}
    for r in rows:
        by_quantity.setdefault(r.get("quantity", "ao"), []).append(r)
    ao = by_quantity.get("ao", [])
    main_ao = [r for r in ao if not is_variant(r["method"])]
    scenes = [s["scene"] for s in meta["scenes"]]
    order = meta.get("preset_order", [])
    size = f'{meta["width"]}x{meta["height"]}'
    out = sys.argv[2]
    stem, ext = os.path.splitext(out)
    where = f"mean over {len(scenes)} scene(s) at {size}"

    single_chart(out, mean_curves(main_ao, order, scenes),
                 f"AO error against time, {where}\n"
                 f'HBAO etc. vs {meta["definition"]}, SSDO vs cosine_linear; reference {meta["converged_rays"]} rays '
                 "per pixel", "RMSE vs converged reference")
    written = [out]

    cols = min(4, max(1, len(scenes)))
    nrows = math.ceil(len(scenes) / cols)
    fig, axes = plt.subplots(nrows, cols, figsize=(4.2 * cols, 3.4 * nrows), dpi=100, squeeze=False)
    for i, scene in enumerate(scenes):
        draw(axes[i // cols][i % cols], curves([r for r in main_ao if r["scene"] == scene], order), scene,
             label_points=False)
    for j in range(len(scenes), nrows * cols):
        axes[j // cols][j % cols].axis("off")
    handles, labels = axes[0][0].get_legend_handles_labels()
    fig.legend(handles, labels, fontsize=8, loc="lower center", ncol=min(4, len(labels)))
    fig.tight_layout(rect=(0, 0.08, 1, 1))
    fig.savefig(stem + "_by_scene" + ext)
    plt.close(fig)
    written.append(stem + "_by_scene" + ext)

    written += variants_charts(stem, ext, ao, order, scenes, meta["definition"])
    lit = {"do": ("directional occlusion (DO)", "Reference.DO: sky map through the open directions + sun"),
           "gi": ("one-bounce GI", "Reference.GI: one bounce from surfaces within r_max")}
    for quantity, (name, reference) in lit.items():
        if not by_quantity.get(quantity):
            continue
        path = f"{stem}_{quantity}{ext}"
        # A bounce variant's DO is its method's, at a higher cost: it would only lie on top of it.
        chosen = [r for r in by_quantity[quantity] if quantity != "do" or not r["method"].endswith("+bounce")]
        single_chart(path, mean_curves(chosen, order, scenes, "rel_rmse"),
                     f"{name} error against time, {where}\nluminance vs {reference}",
                     "relative RMSE = RMSE / mean(reference)")
        written.append(path)
    print("plot_report: wrote " + ", ".join(written))


if __name__ == "__main__":
    main()
