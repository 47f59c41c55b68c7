"""A distortion map of a coin camera: how much each pixel is magnified relative to the same
camera without its coins, from the ray differentials (docs/python.md shows the output).

The footprint of a pixel at distance t along its ray spans (dorg/du + t ddir/du) / W and
(dorg/dv + t ddir/dv) / H; its area against the plain camera's, at t = the distance from the
eye to what it looks at, gives the linear magnification m = sqrt(A_plain / A_coins).

    scripts/python examples/python/distortion_map.py --out out/
"""

from __future__ import annotations

import argparse
import pathlib
import tomllib

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

import anamorph

ROOT = pathlib.Path(__file__).resolve().parents[2]


def footprint_area(rays: dict, t: float) -> np.ndarray:
    du = rays["dorg_du"] + t * rays["ddir_du"]
    dv = rays["dorg_dv"] + t * rays["ddir_dv"]
    return np.linalg.norm(np.cross(du, dv), axis=-1)


def magnification(scene_file: pathlib.Path, width: int, height: int) -> np.ndarray:
    coins = anamorph.load(scene_file).camera.resized(width, height)
    table = tomllib.loads(coins.toml)  # the [camera] table as the scene wrote it
    off = {f"camera.coin.{i}.strength": 0 for i in range(len(table.get("coin", [])))}
    plain = anamorph.load(scene_file, set=off).camera.resized(width, height)
    t = np.linalg.norm(np.subtract(table["look_from"], table["look_at"]))
    a = footprint_area(coins.rays(), t)
    a0 = footprint_area(plain.rays(), t)
    return np.sqrt(a0 / np.maximum(a, 1e-300))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", type=pathlib.Path, default=pathlib.Path("."))
    ap.add_argument("--scene", type=pathlib.Path, default=ROOT / "examples/apps/focus_context.toml")
    ap.add_argument("--width", type=int, default=640)
    ap.add_argument("--height", type=int, default=480)
    args = ap.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)

    m = magnification(args.scene, args.width, args.height)
    img = anamorph.load(args.scene).render(width=args.width, height=args.height, spp=4)["rgba"]
    srgb = np.clip(img[..., :3], 0, 1) ** (1 / 2.2)

    fig, ax = plt.subplots(1, 2, figsize=(12, 4.6), constrained_layout=True)
    ax[0].imshow(srgb)
    ax[0].set_title("render")
    levels = ax[1].imshow(np.log2(m), cmap="RdBu_r", vmin=-2, vmax=2)
    ax[1].set_title("magnification against the camera without coins")
    cbar = fig.colorbar(levels, ax=ax[1], ticks=[-2, -1, 0, 1, 2])
    cbar.ax.set_yticklabels(["1/4", "1/2", "1", "2", "4"])
    for a in ax:
        a.set_axis_off()
    out = args.out / "distortion_map.png"
    fig.savefig(out, dpi=80)
    print(f"{out}: magnification from {m.min():.3f} to {m.max():.3f} "
          f"(median {np.median(m):.3f})")


if __name__ == "__main__":
    main()
