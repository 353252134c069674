"""Render time of the `slicecap` BSDF against Mitsuba's built-in `diffuse`, same scene, same run.

    scripts/python-bench [--size 512] [--spp 64] [--variant llvm_ad_rgb]

A 512 x 512 sphere at 64 spp under the point lights and under the environment map of the
renderer's scenes. Each BSDF is rendered once to warm up (tracing and kernel compilation, also
reported) and then `--repeats` times; the ratio of the best times is the figure to quote.
"""

import argparse
import tempfile
import time

import numpy as np


def best_time(mi, scene_dict, spp, repeats):
    started = time.perf_counter()
    scene = mi.load_dict(scene_dict)
    image = mi.render(scene, spp=spp)
    np.array(image)  # forces evaluation
    first = time.perf_counter() - started
    times = []
    for seed in range(1, repeats + 1):
        started = time.perf_counter()
        np.array(mi.render(scene, spp=spp, seed=seed))
        times.append(time.perf_counter() - started)
    return first, min(times)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--size", type=int, default=512)
    parser.add_argument("--spp", type=int, default=64)
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--variant", default="llvm_ad_rgb")
    args = parser.parse_args()

    import mitsuba as mi

    mi.set_variant(args.variant)
    import slicecap.mitsuba_bsdf
    from slicecap import write_abrdf_exr
    from slicecap.scenes import scene_dict

    slicecap.mitsuba_bsdf.register()
    albedo = [0.6, 0.5, 0.4]
    with tempfile.TemporaryDirectory() as folder:
        path = f"{folder}/lambert.exr"
        write_abrdf_exr(path, np.broadcast_to(np.array(albedo, np.float32) / np.pi, (81, 81, 3)))
        bsdfs = {
            "diffuse": {"type": "diffuse", "reflectance": {"type": "rgb", "value": albedo}},
            "slicecap": {"type": "slicecap", "filename": path},
        }
        print(
            f"{args.variant}, sphere {args.size} x {args.size}, {args.spp} spp, "
            f"best of {args.repeats} after a warm-up"
        )
        for lighting in ("points", "envmap"):
            results = {}
            for name, bsdf in bsdfs.items():
                scene = scene_dict(mi, "sphere", lighting, bsdf, args.size, args.spp)
                results[name] = best_time(mi, scene, args.spp, args.repeats)
                first, best = results[name]
                print(f"  {lighting:6s} {name:8s}  first {first:6.2f} s  best {best:6.2f} s")
            ratio = results["slicecap"][1] / results["diffuse"][1]
            print(f"  {lighting:6s} ratio slicecap / diffuse: {ratio:.2f}")


if __name__ == "__main__":
    main()
