#!/usr/bin/env python3
"""The judge judged: renders the scene of `tests/truth.rs` in Mitsuba 3 (an independent, physically
based renderer) and compares penumbra's visibility images with it.

    PENUMBRA_SAVE_RENDERS=1 PENUMBRA_TRUTH_METHODS=ours,pcss \
        cargo test --release --test truth -- sphere
    python3 tools/mitsuba_truth.py [--spp 1024] [target/penumbra-test-output]

The test writes, per lamp and view, the floor and the casters as OBJ files, the camera and light
as JSON and every method's visibility (the reference's too) as 16-bit PNGs. This script renders
the floor's direct light with and without the casters (Mitsuba's `direct` integrator: direct
light only) and takes their ratio where the floor is what the pixel sees. penumbra's images hold
each pixel's value at its centre; a renderer's pixel is the mean over its footprint, which in a
penumbra a few pixels wide is not the same (it makes a penumbra look less steep), so Mitsuba
renders at `--scale` (odd) times the size and the sub-pixel at each pixel's centre is kept. It
renders twice with different seeds, and prints, per method, the penumbra RMSE against the mean
of the two with Mitsuba's own noise taken out (the two renders' difference measures it), and the
mean signed error in each half of the penumbra (Mitsuba's visibility in (0.02, 0.5] and
(0.5, 0.98)).

The lights as Mitsuba has them: a point light is a `sphere` of the light's radius, a spot light
a one-sided `disk` of its radius facing its direction (its cone leaves the visibility alone), a
rectangle or disk light Mitsuba's `rectangle` or `disk` spanning its half-axes, a sun a disk 1000
units away subtending the sun's angular diameter; each an `area` emitter of uniform radiance. Needs `pip install mitsuba numpy`.
"""
import argparse
import glob
import json
import os
import re

import numpy as np
import mitsuba as mi

mi.set_variant(os.environ.get("MITSUBA_VARIANT", "llvm_ad_rgb"))
mi.set_log_level(mi.LogLevel.Error)
T = mi.ScalarTransform4f


def frame_to(direction):
    """A transform taking +z to `direction` (unit)."""
    d = np.asarray(direction, float)
    d = d / np.linalg.norm(d)
    up = [0.0, 1.0, 0.0] if abs(d[1]) < 0.9 else [1.0, 0.0, 0.0]
    return T().look_at(origin=[0, 0, 0], target=d.tolist(), up=up)


def emitter(light):
    area = {"type": "area", "radiance": {"type": "rgb", "value": 1.0}}
    if light["kind"] == "point":
        return {"type": "sphere", "center": light["position"], "radius": light["radius"], "emitter": area}
    if light["kind"] == "spot":
        to_world = T().translate(light["position"]) @ frame_to(light["direction"]) @ T().scale(light["radius"])
        return {"type": "disk", "to_world": to_world, "emitter": area}
    if light["kind"] in ("rect", "disk"):
        # Mitsuba's rectangle spans [-1, 1]^2 and its disk the unit disk, in their xy planes,
        # facing +z: their x and y become the light's half-axes u and v, z its facing.
        u, v, n = (np.asarray(light[k], float) for k in ("u", "v", "facing"))
        n = n / np.linalg.norm(n)
        c = np.asarray(light["position"], float)
        matrix = np.identity(4)
        matrix[:3, 0], matrix[:3, 1], matrix[:3, 2], matrix[:3, 3] = u, v, n, c
        shape = "rectangle" if light["kind"] == "rect" else "disk"
        return {"type": shape, "to_world": T(matrix.tolist()), "emitter": area}
    d = np.asarray(light["direction"], float)
    d /= np.linalg.norm(d)
    far = 1000.0
    radius = far * np.tan(np.radians(light["angular_diameter_deg"]) / 2)
    to_world = T().translate((-d * far).tolist()) @ frame_to(d.tolist()) @ T().scale(float(radius))
    return {"type": "disk", "to_world": to_world, "emitter": area}


def render(view, meshes, light, spp, scale, seed):
    width, height = (n * scale for n in view["size"])
    cam = view["camera"]
    scene = {
        "type": "scene",
        "integrator": {"type": "direct", "emitter_samples": 1, "bsdf_samples": 0},
        "sensor": {
            "type": "perspective",
            "fov": cam["fov_y_deg"],
            "fov_axis": "y",
            "to_world": T().look_at(origin=cam["eye"], target=cam["target"], up=cam["up"]),
            "film": {"type": "hdrfilm", "width": width, "height": height, "rfilter": {"type": "box"},
                     "pixel_format": "rgb"},
            "sampler": {"type": "multijitter", "sample_count": spp, "seed": seed},
        },
        "light": emitter(light),
    }
    for name, path in meshes.items():
        scene[name] = {"type": "obj", "filename": path, "face_normals": True,
                       "bsdf": {"type": "diffuse", "reflectance": {"type": "rgb", "value": 0.8}}}
    radiance = np.array(mi.render(mi.load_dict(scene)))[..., 1]
    depth_scene = dict(scene)
    depth_scene["integrator"] = {"type": "aov", "aovs": "d:depth"}
    depth_scene["sensor"] = dict(scene["sensor"], sampler={"type": "independent", "sample_count": 1})
    depth = np.array(mi.render(mi.load_dict(depth_scene)))[..., 0]
    return radiance, depth


def visibility(view, out, lamp, spp, scale, seed):
    """Mitsuba's visibility at each pixel's centre, NaN where the pixel does not see the floor."""
    floor = os.path.join(out, f"truth_{lamp}_floor.obj")
    casters = os.path.join(out, f"truth_{lamp}_casters.obj")
    lit, depth = render(view, {"floor": floor, "casters": casters}, view["light"], spp, scale, seed)
    unshadowed, floor_depth = render(view, {"floor": floor}, view["light"], spp, scale, seed)
    on_floor = (np.abs(depth - floor_depth) < 1e-3 * np.maximum(floor_depth, 1e-6)) & (unshadowed > 0.0)
    # Sub-pixels beside a caster's silhouette are left out: every one of the 3x3 block around
    # the kept one must see the floor.
    padded = np.pad(on_floor, 1, constant_values=False)
    on_floor = np.all([padded[1 + dy:padded.shape[0] - 1 + dy, 1 + dx:padded.shape[1] - 1 + dx]
                       for dy in (-1, 0, 1) for dx in (-1, 0, 1)], axis=0)
    truth = np.where(on_floor, lit / np.maximum(unshadowed, 1e-30), np.nan)
    return truth[scale // 2::scale, scale // 2::scale]


def compare(out, lamp, view_index, spp, scale):
    view = json.load(open(os.path.join(out, f"truth_{lamp}_{view_index}.json")))
    a = visibility(view, out, lamp, spp, scale, 1)
    b = visibility(view, out, lamp, spp, scale, 2)
    truth = (a + b) / 2
    rows = {}
    for path in sorted(glob.glob(os.path.join(out, f"truth_{lamp}_{view_index}_*.png"))):
        method = re.sub(r".*_\d+_(.*)\.png", r"\1", path)
        image = np.array(mi.Bitmap(path)).astype(float)
        if image.ndim == 3:
            image = image[..., 0]
        image /= 65535.0
        half = [(truth > 0.02) & (truth <= 0.5), (truth > 0.5) & (truth < 0.98)]
        both = half[0] | half[1]
        # The mean of two renders carries a quarter of their squared difference as noise.
        noise = float(np.mean((a[both] - b[both]) ** 2) / 4)
        mse = float(np.mean((image[both] - truth[both]) ** 2))
        rows[method] = (
            float(np.sqrt(max(mse - noise, 0.0))),
            float(np.mean(image[half[0]] - truth[half[0]])),
            float(np.mean(image[half[1]] - truth[half[1]])),
            int(both.sum()),
            float(np.sqrt(noise)),
        )
    return view["lamp"], rows


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("out", nargs="?", default="target/penumbra-test-output")
    parser.add_argument("--spp", type=int, default=1024, help="samples per sub-pixel (a square, for the multijitter sampler)")
    parser.add_argument("--scale", type=int, default=5, help="Mitsuba's sub-pixels per pixel side (odd)")
    parser.add_argument("--views", default=None, help="comma-separated view numbers (default: all dumped)")
    parser.add_argument("--report", default=None,
                        help="also write the table as a Markdown report to this path, headed by the command, "
                             "Mitsuba's version and variant and the repository's commit")
    args = parser.parse_args()
    dumped = sorted(glob.glob(os.path.join(args.out, "truth_*_*.json")))
    if not dumped:
        raise SystemExit(f"no truth_*.json in {args.out}: run tests/truth.rs with PENUMBRA_SAVE_RENDERS=1 first")
    if args.scale % 2 == 0:
        raise SystemExit("--scale must be odd, so that a sub-pixel lies at each pixel's centre")
    lines = [
        "| lamp | view | method | penumbra RMSE vs Mitsuba | inner half signed | outer half signed | pixels | Mitsuba's noise |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for line in lines:
        print(line)
    for path in dumped:
        lamp, view_index = re.match(r".*truth_(\d+)_(\d+)\.json", path).groups()
        if args.views and view_index not in args.views.split(","):
            continue
        name, rows = compare(args.out, lamp, view_index, args.spp, args.scale)
        for method, (rmse, inner, outer, n, noise) in rows.items():
            lines.append(f"| {name} | {view_index} | {method} | {rmse:.4f} | {inner:+.4f} | {outer:+.4f} | {n} | {noise:.4f} |")
            print(lines[-1])
    if args.report:
        write_report(args, lines)


def write_report(args, lines):
    """The table as a Markdown file, with what produced it."""
    import subprocess
    import sys
    try:
        commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True, text=True,
                                check=True).stdout.strip()
        dirty = subprocess.run(["git", "status", "--porcelain", "--untracked-files=no"], capture_output=True,
                               text=True, check=True).stdout.strip()
        if dirty:
            commit += " with uncommitted changes"
    except (OSError, subprocess.CalledProcessError):
        commit = "unknown (no git)"
    header = [
        "# penumbra against Mitsuba 3",
        "",
        f"Written by `python3 tools/mitsuba_truth.py {' '.join(sys.argv[1:])}` from the images that",
        "`tests/truth.rs` saved (`PENUMBRA_SAVE_RENDERS=1`), on the repository at commit "
        f"{commit}; Mitsuba {mi.__version__}, variant `{mi.variant()}`, {args.spp} samples per",
        f"sub-pixel, {args.scale}x{args.scale} sub-pixels per pixel, the centre one kept. Penumbra",
        "RMSE is over the pixels where Mitsuba's visibility is in (0.02, 0.98), with Mitsuba's own",
        "noise (the difference of two seeds) taken out; the halves are (0.02, 0.5] and (0.5, 0.98).",
        "",
    ]
    with open(args.report, "w") as f:
        f.write("\n".join(header + lines) + "\n")
    print(f"wrote {args.report}")


if __name__ == "__main__":
    main()
