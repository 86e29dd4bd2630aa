#!/usr/bin/python3
"""Plots facet-bench --pareto's CSV: error against frame time, one panel per
scene, each scene's Pareto front joined and labelled.

    plot_pareto.py pareto.csv pareto.png

Uses Debian's python3-matplotlib (scripts/install-deps installs it).
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

SCENES = [
    ("default", "MSAA, texture filter, sub-pixel bits", "msaa"),
    ("lit", "MSAA, filter, bits, per pixel or vertex", "msaa"),
    ("phong", "MSAA, sub-pixel bits", "msaa"),
    ("toon", "MSAA, sub-pixel bits", "msaa"),
    ("shadow", "shadow-map size, PCF kernel", "shadow_map_size"),
    ("ao", "AO samples, radius, resolution", "ao_samples"),
    ("gallery", "pbr and normal maps: MSAA, filter, bits", "msaa"),
    ("environment", "environment size, prefilter samples", "environment_size"),
]


def label(row, scene):
    if scene in ("default", "lit", "gallery"):
        vertex = " vtx" if row["per_pixel"] == "0" else ""
        name = row["filter"]
        name = "an" + name[len("anisotropic"):] if name.startswith("anisotropic") else name[:3]
        return f"{row['msaa']}x {name} {row['subpixel_bits']}b{vertex}"
    if scene in ("phong", "toon"):
        return f"{row['msaa']}x {row['subpixel_bits']}b"
    if scene == "shadow":
        return f"{row['shadow_map_size']} pcf{row['pcf_kernel']}"
    if scene == "environment":
        return f"{row['environment_size']} ggx{row['environment_samples']}"
    return f"{row['ao_samples']} r{float(row['ao_radius']):.2g} {row['ao_resolution']}"


def main(csv_path, png_path):
    with open(csv_path, newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        sys.exit(f"{csv_path}: no rows")
    threads = rows[0]["threads"]
    columns = 3
    rows_of_panels = (len(SCENES) + columns - 1) // columns
    fig, axes = plt.subplots(rows_of_panels, columns, figsize=(6 * columns, 5.2 * rows_of_panels))
    for ax, (scene, knobs, colour_by) in zip(axes.flat, SCENES):
        points = [r for r in rows if r["scene"] == scene]
        if not points:
            ax.set_visible(False)
            continue
        keys = sorted({r[colour_by] for r in points}, key=float)
        cmap = plt.get_cmap("viridis", max(len(keys), 2))
        for i, key in enumerate(keys):
            group = [r for r in points if r[colour_by] == key]
            ax.scatter([float(r["median_ms"]) for r in group],
                       [float(r["rmse"]) for r in group],
                       color=cmap(i), s=22, label=f"{colour_by} = {key}", zorder=2)
        front = sorted((r for r in points if r["pareto"] == "1"),
                       key=lambda r: float(r["median_ms"]))
        ax.plot([float(r["median_ms"]) for r in front], [float(r["rmse"]) for r in front],
                color="crimson", lw=1.2, zorder=1, label="Pareto front")
        for r in front:
            ax.annotate(label(r, scene), (float(r["median_ms"]), float(r["rmse"])),
                        textcoords="offset points", xytext=(4, 4), fontsize=7, color="crimson")
        ax.set_title(f"{scene}: {knobs}", fontsize=10)
        ax.set_xlabel(f"median frame time, ms ({threads} thread{'' if threads == '1' else 's'})")
        ax.set_ylabel("RMSE against the reference (sRGB, 0..1)")
        ax.set_yscale("log")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7, loc="upper right")
    for ax in list(axes.flat)[len(SCENES):]:  # the grid's slots past the last scene
        ax.set_visible(False)
    fig.suptitle("facet: error against run time (facet-bench --pareto)")
    fig.tight_layout()
    fig.savefig(png_path, dpi=110)


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2])
