"""Contact queries on the smooth torso: closest points, distances, normals and the distance
Hessian of points where garment nodes are (medians; docs/performance.md, section ``query``).

Points: uniformly around and along torso M (0.78-1.27 m), put on the surface along the ray from
the axis and moved off it by a normal-distributed 3 mm in every direction (the Newton line
search's trials are this far off, or nearer). ``query`` is `SmoothTorso.query` (closest-point
Newton from the ray's point, to 1e-13 m), ``hessian`` the distance Hessian at the closest points
(Newton's contact curvature term). Run:

    .venv/bin/python benchmarks/bench_query.py [--counts 10000 100352] [--repeat 7] [--no-write]
"""

from __future__ import annotations

import argparse
import platform

import numpy as np
from _table import markdown_table, median_seconds, replace_section

from cloth.files.body import body_from_config


def near_torso(body, count: int, rng: np.random.Generator) -> np.ndarray:
    """``count`` points ((count, 3), m) about 3 mm off the smooth torso's surface."""
    z = rng.uniform(0.78, 1.27, count)
    angle = rng.uniform(0.0, 2.0 * np.pi, count)
    direction = np.column_stack([0.3 * np.cos(angle), 0.3 * np.sin(angle), z])
    on, _ = body.locate(direction)
    return on + rng.normal(scale=0.003, size=on.shape)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--counts", nargs="+", type=int, default=[10_000, 100_352])
    parser.add_argument("--repeat", type=int, default=7)
    parser.add_argument("--no-write", action="store_true", help="print, leave the docs alone")
    args = parser.parse_args()
    body = body_from_config({"torso": {"size": "M"}})[0]
    rng = np.random.default_rng(1)
    rows = []
    for count in args.counts:
        points = near_torso(body, count, rng)
        closest = body.query(points)[1]
        query = median_seconds(lambda p=points: body.query(p), args.repeat)
        hessian = median_seconds(lambda q=closest: body.hessian(q), args.repeat)
        rows.append([f"{count:,}", f"{query:.3f}", f"{hessian:.3f}", f"{1e6 * query / count:.2f}"])
        print(rows[-1], flush=True)
    text = (
        f"Medians of {args.repeat} runs on {platform.machine()}, points about 3 mm off torso M.\n\n"
        + markdown_table(
            ["points", "query [s]", "distance Hessian [s]", "query per point [us]"], rows
        )
    )
    print(text)
    if not args.no_write:
        replace_section("query", text)


if __name__ == "__main__":
    main()
