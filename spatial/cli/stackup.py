"""`implicad stackup STACK.py`: tolerance stack-up of a clearance in an assembly.

The stack file defines ``parts(values)`` (named solids built from a dict of
parameter values), ``tolerances`` (a dict of `spatial.inspection.Tolerance`,
or plain numbers for fixed values) and ``between = ("a", "b")``, the two
parts whose signed gap is stacked up.  Prints the worst case, RSS and
Monte-Carlo results with the share of each tolerance; exit status 1 when the
worst case interferes.
"""

from __future__ import annotations

import json

NAME = "stackup"
HELP = "tolerance stack-up of a clearance: worst case, RSS, Monte-Carlo, probability of interference"
DESCRIPTION = (
    "Stack up the tolerances of a stack file (.py defining parts(values), tolerances and between=(a, b)) "
    "to the signed gap between two parts: worst case over the tolerance corners, RSS, seeded "
    "Monte-Carlo, the probability of interference and each tolerance's share. Exit 1 when the worst "
    "case interferes."
)


def add_arguments(parser) -> None:
    parser.add_argument("stack", metavar="STACK", help="stack file (.py)")
    parser.add_argument("--samples", type=int, default=1000, metavar="N", help="Monte-Carlo samples (default 1000)")
    parser.add_argument("--seed", type=int, default=0, help="random seed (default 0)")
    parser.add_argument("--check", action="store_true", help="check the worst corner with the interference test")
    parser.add_argument("--picture", metavar="PNG", help="distribution and contributions")
    parser.add_argument("--json", action="store_true", help="print the result as JSON")


def _load(path):
    import os
    import runpy

    if not str(path).endswith(".py"):
        raise ValueError(f"{path}: expected a .py stack file")
    if not os.path.exists(path):
        raise FileNotFoundError(2, "No such file", path)
    try:
        ns = runpy.run_path(str(path), run_name="__implicad_stack__")
    except (Exception, SystemExit) as exc:  # the file is the user's own program
        raise ValueError(f"{path}: raised {type(exc).__name__}: {exc}") from None
    for key in ("parts", "tolerances", "between"):
        if key not in ns:
            raise ValueError(f"{path}: defines no '{key}' (a stack file needs parts(values), tolerances, between)")
    return ns["parts"], ns["tolerances"], ns["between"]


def run(args) -> int:
    from ..inspection import stackup, stackup_picture
    from ._output import check_output

    if args.samples < 0:
        raise ValueError(f"--samples: expected a non-negative integer, got {args.samples}")
    if args.picture:
        check_output(args.picture, (".png",), "a picture")
    build, tols, between = _load(args.stack)
    r = stackup(build, tols, between=between, samples=args.samples, seed=args.seed, check_worst=args.check)
    if args.picture:
        stackup_picture(r, args.picture)
    if args.json:
        d = r.to_dict()
        print(json.dumps(d, indent=2))
    else:
        print(f"stack-up of {r.label} in {args.stack}")
        print(f"nominal {r.nominal:.6g}; worst case {r.worst_min:.6g} .. {r.worst_max:.6g} "
              f"(worst corner {', '.join(f'{k}={v:g}' for k, v in r.worst_corner.items())})")
        print(f"RSS: mean {r.rss_mean:.6g}, sigma {r.rss_std:.4g}")
        if len(r.samples):
            print(f"Monte-Carlo ({len(r.samples)} samples, seed {r.seed}): mean {r.mc_mean:.6g}, "
                  f"sigma {r.mc_std:.4g}, min {r.samples.min():.6g}, max {r.samples.max():.6g}")
            print(f"probability of interference: {r.probability_interference:.4%} +/- {r.probability_error:.2%}")
        print(r.table())
        if r.worst_check is not None:
            inter = r.worst_check["interfering"]
            print("worst corner, interference check: " + ("; ".join(f"{a} / {b} share {v:.4g}" for a, b, v in inter)
                                                          if inter else "no interference"))
        if args.picture:
            print(f"wrote {args.picture}")
    return 1 if r.worst_min < 0 else 0
