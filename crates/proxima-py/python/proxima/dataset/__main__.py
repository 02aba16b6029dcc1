"""``python -m proxima.dataset INPUT [INPUT ...] OUTPUT_DIR [options]``: signed-distance
(or occupancy) samples of every mesh of a corpus, one ``.npz`` per mesh.

INPUT: a folder (its mesh files, recursively), a glob (quote it: "meshes/**/*.obj"),
a mesh file, or a text file listing mesh paths one a line. Prints a JSON summary;
exits with 1 when some mesh failed (see OUTPUT_DIR/failures.jsonl), 0 otherwise.
"""

import argparse
import sys

from . import _print_summary, sample_corpus
from .sampling import KINDS, NORMALIZATIONS


def positive_int(text):
    value = int(text)
    if value < 1:
        raise argparse.ArgumentTypeError(f"{text} is not an integer >= 1")
    return value


def main(argv=None):
    parser = argparse.ArgumentParser(
        prog="python -m proxima.dataset",
        description=__doc__.split("\n\n")[0].replace("``", ""),
        epilog="Outputs: OUTPUT_DIR/<name>.npz with points (float32 n x 3), sdf (float32 n), "
        "occupancy (bool n, --kind occupancy), grid (float32 N x N x N, --grid N), scale and offset "
        "(original = normalized * scale + offset). See help(proxima.dataset).",
    )
    parser.add_argument("inputs", nargs="+", metavar="INPUT", help="folder, glob, mesh file or list file")
    parser.add_argument("output_dir", metavar="OUTPUT_DIR")
    parser.add_argument("--points", type=int, default=250_000, help="points per mesh (default 250000)")
    parser.add_argument("--kind", choices=KINDS, default="sdf", help="sdf, or occupancy (adds occupancy = sdf < 0)")
    parser.add_argument("--grid", type=positive_int, default=None, metavar="N", help="also an N^3 grid of signed distances")
    parser.add_argument("--address", default=None, help='Ray cluster: "auto" or "ray://host:port" (default: a local instance)')
    parser.add_argument("--engine", choices=("ray", "local"), default="ray", help="ray (default) or local (no Ray)")
    parser.add_argument(
        "--normalize", choices=tuple(NORMALIZATIONS), default=None,
        help="unit-sphere (DeepSDF) or unit-cube (Occupancy Networks); default: unit-sphere for sdf, unit-cube for occupancy",
    )
    parser.add_argument("--padding", type=float, default=None, help="normalization padding (default 0.03 unit-sphere, 0 unit-cube)")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--near-sigma", type=float, default=0.01, help="std. dev. of the near-surface offsets, normalized units (default 0.01)")
    parser.add_argument("--uniform-fraction", type=float, default=0.1, help="fraction of the points uniform in the sampling cube (default 0.1)")
    parser.add_argument("--workers", type=positive_int, default=None, help="meshes at a time (default: CPUs / threads)")
    parser.add_argument("--threads", type=positive_int, default=None, help="threads per mesh (default 1)")
    parser.add_argument("--local-pool", choices=("thread", "process"), default="thread", help="the local engine's pool (default thread)")
    parser.add_argument("--compress", action="store_true", help="np.savez_compressed")
    parser.add_argument("--deepsdf", action="store_true", help="also DeepSDF's pos/neg arrays (x, y, z, sdf rows split by sign)")
    parser.add_argument("--max-task-retries", type=int, default=3, help="Ray: retries of a mesh whose worker died (default 3)")
    parser.add_argument("--no-progress", action="store_true", help="no Ray progress bars")
    args = parser.parse_args(argv)
    try:
        summary = sample_corpus(
            args.inputs if len(args.inputs) > 1 else args.inputs[0],
            args.output_dir,
            n_points=args.points,
            near_sigma=args.near_sigma,
            grid=args.grid,
            kind=args.kind,
            seed=args.seed,
            address=args.address,
            engine=args.engine,
            normalize=args.normalize,
            padding=args.padding,
            uniform_fraction=args.uniform_fraction,
            workers=args.workers,
            threads=args.threads,
            local_pool=args.local_pool,
            compress=args.compress,
            deepsdf=args.deepsdf,
            max_task_retries=args.max_task_retries,
            progress=not args.no_progress,
        )
    except (ValueError, FileNotFoundError, ImportError) as error:
        print(f"error: {error}", file=sys.stderr)
        return 2
    _print_summary(summary)
    return 1 if summary["failed"] else 0


if __name__ == "__main__":
    sys.exit(main())
