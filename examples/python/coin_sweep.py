"""A parameter sweep: the focus+context scene with its middle coin's strength stepped from 0
(no coin) to 0.8, one render per value, laid out as a contact sheet.

    scripts/python examples/python/coin_sweep.py --out out/
"""

from __future__ import annotations

import argparse
import pathlib

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

import anamorph

ROOT = pathlib.Path(__file__).resolve().parents[2]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", type=pathlib.Path, default=pathlib.Path("."))
    ap.add_argument("--scene", type=pathlib.Path, default=ROOT / "examples/apps/focus_context.toml")
    ap.add_argument("--coin", type=int, default=0, help="which [[camera.coin]] to sweep")
    ap.add_argument("--width", type=int, default=320)
    ap.add_argument("--height", type=int, default=240)
    ap.add_argument("--steps", type=int, default=6)
    args = ap.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)

    strengths = np.linspace(0, 0.8, args.steps)
    cols = 3
    rows = (len(strengths) + cols - 1) // cols
    fig, axes = plt.subplots(rows, cols, figsize=(4 * cols, 3.2 * rows), constrained_layout=True)
    for ax in axes.flat:
        ax.set_axis_off()
    for ax, m in zip(axes.flat, strengths):
        scene = anamorph.load(args.scene, set={f"camera.coin.{args.coin}.strength": float(m)})
        rgba = scene.render(width=args.width, height=args.height, spp=4)["rgba"]
        ax.imshow(np.clip(rgba[..., :3], 0, 1) ** (1 / 2.2))
        ax.set_title(f"camera.coin.{args.coin}.strength = {m:.2f}")
    out = args.out / "coin_sweep.png"
    fig.savefig(out, dpi=72)
    print(f"{out}: {len(strengths)} renders of coin {args.coin}, strength 0 to 0.8")


if __name__ == "__main__":
    main()
