#!/usr/bin/env python3
"""A sun-elevation sweep with `import sylva`: one scene rendered at several sun elevations, the
frames stacked into a numpy array, and the mean band radiance against elevation plotted with
matplotlib (docs/python.md).

    PYTHONPATH=build/python python3 python/examples/sun_sweep.py --out sweep.png
"""
import argparse

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import sylva  # noqa: E402


def sweep(scene, elevations, res, spp):
    """A (len(elevations), height, width, 3) stack of the visible band."""
    frames = []
    for elevation in elevations:
        image = sylva.render(scene, res=res, spp=spp, overrides={"sun.elevation": float(elevation)})
        frames.append(np.stack([image["R"], image["G"], image["B"]], axis=-1))
    return np.stack(frames)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scene", default=None, help="scene file (default: the built-in forest)")
    parser.add_argument("--res", default="160x90")
    parser.add_argument("--spp", type=int, default=4)
    parser.add_argument("--out", default="sun_sweep.png")
    args = parser.parse_args()
    elevations = [10, 25, 40, 55, 70]
    stack = sweep(args.scene, elevations, args.res, args.spp)
    fig, (ax_img, ax_plot) = plt.subplots(2, 1, figsize=(10, 6.5), height_ratios=[1, 1.6])
    strip = np.concatenate(list(stack), axis=1)
    ax_img.imshow(np.clip(strip / max(np.percentile(strip, 99), 1e-9), 0, 1) ** (1 / 2.2))
    ax_img.set_title("sun elevation " + ", ".join(f"{e}°" for e in elevations))
    ax_img.axis("off")
    for c, colour in enumerate("rgb"):
        ax_plot.plot(elevations, stack[..., c].mean(axis=(1, 2)), colour + "o-", label="RGB"[c])
    ax_plot.set_xlabel("sun elevation (degrees)")
    ax_plot.set_ylabel("mean band radiance (W m⁻² sr⁻¹ nm⁻¹)")
    ax_plot.legend()
    fig.tight_layout()
    fig.savefig(args.out, dpi=100)
    print(f"{stack.shape} stack, plot in {args.out}")


if __name__ == "__main__":
    main()
