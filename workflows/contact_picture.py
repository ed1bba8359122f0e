"""The contact region at peak contact pressure from a run's fields (rods.fe.fields.render_contact).

    python workflows/contact_picture.py --fields output/paper/fields --out results/contact-fields

Writes OUT.png (von Mises on the deformed mesh, the contact pressure; pyvista off-screen) and OUT.json (the
frame: time, peak contact pressure and von Mises, the run's model, scene and mesh), which REPORT.md renders.
A series that is not the run's of the summary.json beside it (an earlier run's, left in a reused folder by a
version that kept it) is refused, exit 2 (rods.fe.fields.check_run).
"""

from __future__ import annotations

import _cli
from rods.preflight import input_dir


def main(argv: list[str] | None = None) -> int:
    ap = _cli.bare_parser(__doc__)
    ap.add_argument("--fields", required=True, help="a run folder with fields.xdmf (and its summary.json)")
    ap.add_argument("--out", required=True, help="output path without suffix (.png and .json are written)")
    args = ap.parse_args(argv)
    remedy = "give the folder of a run with fields (the 'fields' effect or fe.field_interval > 0)"
    run = input_dir(args.fields, ("fields.xdmf",), "--fields", remedy)  # before any folder is made; a killed run
    # has no summary.json: its series' own scene names the picture (rods.fe.fields.contact_picture)
    from rods.fe.fields import check_run, contact_picture

    check_run(run, "--fields")  # the series is the run's of summary.json (else its scene would label another's)
    out = _cli.output_file(args.out, "--out")  # a prefix: OUT.png, OUT.json
    if not _cli._is_rank0():  # a serial tool under mpirun: one picture, one line (every rank drew and printed it)
        return 0
    out.parent.mkdir(parents=True, exist_ok=True)
    t = contact_picture(run, out)["time"]
    print(f"wrote {out.with_suffix('.png')} and {out.with_suffix('.json')} (t = {t:.6g} s)")
    return 0


if __name__ == "__main__":
    _cli.entry(main)
