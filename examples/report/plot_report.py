#!/usr/bin/env python3
"""Draws obscura_report's error-against-run-time chart from results.json.

usage: plot_report.py results.json error_vs_time.png

Writes error_vs_time.png (log-log, x = time per frame in ms, y = AO RMSE, both the mean
over the report's scenes): one curve per method + device through the quality presets
(HBAO against the report's definition, SSDO against cosine_linear), and the ray tracer's
own curve through its AO ray counts, once per definition in play. Points are labelled with
their preset or ray count (one curve per method: its devices run the same presets). Also
writes <stem>_by_scene.png with the same chart for each scene, and, when the rows hold GI
(quantity "gi": ssdo+bounce against the ray tracer's DiffInd), <stem>_gi.png.
"""
import json
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

RAYTRACE = "raytrace"


def curves(rows, preset_order):
    """{(method, device): [(label, time_ms, rmse), ...]} in preset / ray-count order."""
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
        result[key] = [(lab, r["time_ms"], r["rmse"]) for lab, r in zip(labels, group)]
    return result


def mean_curves(rows, preset_order, scenes):
    """Per (method, device) and point label: mean time and mean RMSE over the scenes."""
    per_scene = [curves([r for r in rows if r["scene"] == s], preset_order) for s in scenes]
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


def draw(ax, curve_map, title, label_points=True, ylabel="RMSE vs converged reference"):
    colours = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    obscura_keys = sorted(k for k in curve_map if k[0] != RAYTRACE)
    markers = "osD^v<>p"
    labelled = set()  # methods whose presets are labelled (devices share sample counts, so one curve each)
    traced = sorted(k for k in curve_map if k[0] == RAYTRACE)
    for i, key in enumerate(obscura_keys + traced):
        pts = [p for p in curve_map[key] if p[1] > 0 and p[2] > 0]
        if not pts:
            continue
        xs, ys = [p[1] for p in pts], [p[2] for p in pts]
        if key[0] == RAYTRACE:
            style = "k--x" if traced.index(key) == 0 else "k:+"
            ax.plot(xs, ys, style, lw=1.2, ms=6, label=f"ray traced ({key[1]}, {key[2]})")
        else:
            ax.plot(xs, ys, "-", marker=markers[i % len(markers)], color=colours[i % len(colours)], lw=1.5, ms=5,
                    label=f"{key[0]} on {key[1]}")
        # ssdo+bounce runs ssdo's presets at the same AO: its labels would sit on ssdo's (unless it is alone)
        quiet = key[0] == "ssdo+bounce" and any(k[0] == "ssdo" for k in curve_map)
        if label_points and not quiet and key[:1] + key[2:] not in labelled:
            labelled.add(key[:1] + key[2:])
            for lab, x, y in pts:
                ax.annotate(lab, (x, y), textcoords="offset points", xytext=(4, 3), fontsize=7)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("time per frame (ms)")
    ax.set_ylabel(ylabel)
    ax.set_title(title, fontsize=10)
    ax.grid(True, which="both", lw=0.3, alpha=0.6)


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    with open(sys.argv[1]) as f:
        data = json.load(f)
    meta, rows = data["meta"], data["rows"]
    rows = [r for r in rows if r.get("rmse") is not None and math.isfinite(r["rmse"])]
    gi_rows = [r for r in rows if r.get("quantity", "ao") == "gi"]
    rows = [r for r in rows if r.get("quantity", "ao") == "ao"]
    scenes = [s["scene"] for s in meta["scenes"]]
    order = meta.get("preset_order", [])
    size = f'{meta["width"]}x{meta["height"]}'
    out = sys.argv[2]

    fig, ax = plt.subplots(figsize=(8, 6), dpi=120)
    draw(ax, mean_curves(rows, order, scenes),
         f"AO error against time, mean over {len(scenes)} scene(s) at {size}\n"
         f'HBAO vs {meta["definition"]}, SSDO vs cosine_linear; reference {meta["converged_rays"]} rays per pixel')
    ax.legend(fontsize=8, loc="best")
    fig.tight_layout()
    fig.savefig(out)
    plt.close(fig)

    cols = min(4, max(1, len(scenes)))
    nrows = math.ceil(len(scenes) / cols)
    fig, axes = plt.subplots(nrows, cols, figsize=(4.2 * cols, 3.4 * nrows), dpi=100, squeeze=False)
    for i, scene in enumerate(scenes):
        draw(axes[i // cols][i % cols], curves([r for r in rows if r["scene"] == scene], order), scene)
    for j in range(len(scenes), nrows * cols):
        axes[j // cols][j % cols].axis("off")
    handles, labels = axes[0][0].get_legend_handles_labels()
    fig.legend(handles, labels, fontsize=8, loc="lower center", ncol=min(4, len(labels)))
    fig.tight_layout(rect=(0, 0.06, 1, 1))
    stem, ext = os.path.splitext(out)
    fig.savefig(stem + "_by_scene" + ext)
    plt.close(fig)
    written = [out, stem + "_by_scene" + ext]
    if gi_rows:
        fig, ax = plt.subplots(figsize=(8, 6), dpi=120)
        draw(ax, mean_curves(gi_rows, order, scenes),
             f"one-bounce GI error against time, mean over {len(scenes)} scene(s) at {size}\n"
             "luminance of GI / pi vs ray-traced DiffInd (which includes light from beyond r_max and off screen)",
             ylabel="RMSE of GI / pi vs DiffInd (luminance)")
        ax.set_yscale("linear")
        ax.set_ylim(bottom=0)
        ax.legend(fontsize=8, loc="best")
        fig.tight_layout()
        fig.savefig(stem + "_gi" + ext)
        plt.close(fig)
        written.append(stem + "_gi" + ext)
    print("plot_report: wrote " + ", ".join(written))


if __name__ == "__main__":
    main()
