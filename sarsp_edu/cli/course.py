"""``sarsp-edu course``: the source notebooks run, the student notebooks made, static pages and a students' copy."""

from __future__ import annotations

import sys

from .arguments import check_file, check_out, check_writable


def _check_pages_out(parser, out, overwrite: bool) -> None:
    """Refuse a pages folder that holds results, or pages already unless ``--overwrite``."""
    from .arguments import _MARKERS, results_of

    held = next((kind for kind, marker in _MARKERS.items() if (out / marker).exists()), None)
    if held:
        parser.error(f"--out {out} holds {results_of(held)}; give the pages a folder of their own")
    pages = sorted(p.name for p in out.glob("*.html")) if out.is_dir() else []
    if pages and not overwrite:
        parser.error(f"--out {out} holds pages already ({', '.join(pages[:3])}{' ...' if len(pages) > 3 else ''}); "
                     "add --overwrite to replace them, or give a new folder")
    check_writable(parser, "--out", str(out), out)


#: what ``sarsp-edu course`` needs beyond the package's own dependencies (the extra ``course``)
COURSE_MODULES = ("nbformat", "nbclient", "nbconvert", "jinja2")


def _course(args, parser) -> int:
    import importlib.util
    from pathlib import Path

    from ..teaching.course import NotebookFailed, execute_sources, write_handout, write_pages, write_student_notebooks

    missing = [name for name in COURSE_MODULES if importlib.util.find_spec(name) is None]
    if missing:
        parser.error(f"sarsp-edu course needs {', '.join(missing)}, which a plain install leaves out: "
                     "pip install 'sarsp_edu[course]'")

    if args.lecturer and args.action != "pages":
        parser.error(f"--lecturer makes the lecturer's edition of the pages; '{args.action}' has none")
    if args.only and args.action in ("pages", "handout"):  # a flag that would change nothing: refused, not ignored
        parser.error(f"--only picks the notebooks of 'sources' and 'student'; '{args.action}' writes every "
                     "tutorial's (drop --only)")
    if args.action in ("sources", "student", "pages"):
        try:
            if args.action == "sources":
                written = execute_sources(args.tutorials, only=args.only)
            elif args.action == "student":
                written = write_student_notebooks(args.tutorials, run=not args.no_execute, only=args.only,
                                                  overwrite=args.overwrite, report=print)
            else:
                if args.out is None:
                    parser.error("pages needs --out DIR")
                _check_pages_out(parser, Path(args.out), args.overwrite)
                written = [write_pages(args.tutorials, args.out, edition="lecturer" if args.lecturer else "student")]
        except (FileNotFoundError, ValueError) as exc:
            parser.error(str(exc))
        except NotebookFailed as exc:
            print(f"error: {exc}", file=sys.stderr)
            return 1
        for path in written:
            print(f"wrote {path}")
        return 0
    if args.out is not None and args.zip is not None:
        parser.error("handout takes --out DIR or --zip FILE, not both")
    if args.out is None and args.zip is None:
        parser.error("handout needs --out DIR or --zip FILE")
    if args.out is not None:
        if any(Path(args.out).glob("tutorials/[0-9][0-9]_*.ipynb")):
            parser.error(f"--out {args.out} holds a course hand-out already (written earlier); give a new or empty "
                         "folder, or remove it first")
        check_out(parser, args.out, "handout")
    else:
        if Path(args.zip).suffix.lower() != ".zip":
            parser.error(f"--zip {args.zip}: name a .zip file")
        if Path(args.root).resolve() in Path(args.zip).resolve().parents:
            parser.error(f"--zip {args.zip} lies inside the repository --root {args.root}, whose files it could "
                         "replace; write it outside")
        check_file(parser, "--zip", args.zip, overwrite=args.overwrite)
    try:
        made = write_handout(args.root, out=args.out, zip_path=args.zip)
    except (FileNotFoundError, ValueError) as exc:
        parser.error(str(exc))
    print(f"the students' copy of the course (no sources, no solutions) is in {made}")
    return 0
