"""Output files and folders: nothing is overwritten or lost without asking, and each refusal says why."""

from __future__ import annotations

import os
import stat
import zipfile
from pathlib import Path

from sarsp_edu.cli import main

from .test_cli import _usage_error as usage_error

ROOT = Path(__file__).resolve().parents[1]
SWEEP = ROOT / "results" / "sweep-reduced"


def test_tables_write_markdown_only_to_a_regular_file(tmp_path, capsys):
    target = tmp_path / "kept.md"
    target.write_text("someone's notes\n")
    link = tmp_path / "link.md"
    link.symlink_to(target)
    err = usage_error(["tables", str(SWEEP), "--markdown", str(link)], capsys)
    assert f"--markdown {link} is a symbolic link; give the file itself or a new name" in err
    assert link.is_symlink() and target.read_text() == "someone's notes\n"
    err = usage_error(["tables", str(SWEEP), "--markdown", os.devnull], capsys)
    assert f"--markdown {os.devnull} is not a regular file (a device, a pipe or a socket)" in err
    err = usage_error(["tables", str(SWEEP), "--markdown", str(target)], capsys)  # someone's file: kept
    assert f"--markdown {target} exists; add --overwrite to replace it, or give a new name" in err
    assert target.read_text() == "someone's notes\n"
    assert main(["tables", str(SWEEP), "--markdown", str(target), "--overwrite"]) == 0  # regenerated, as asked
    assert target.read_text().startswith("#")


def test_the_course_pages_refuse_a_results_folder_and_existing_pages_without_overwrite(tmp_path, capsys):
    err = usage_error(["course", "pages", "--tutorials", str(ROOT / "tutorials"), "--out", str(SWEEP)], capsys)
    assert f"--out {SWEEP} holds a sweep's results; give the pages a folder of their own" in err
    out = tmp_path / "pages"
    out.mkdir()
    (out / "index.html").write_text("<p>the lecturer's own page</p>")
    err = usage_error(["course", "pages", "--tutorials", str(ROOT / "tutorials"), "--out", str(out)], capsys)
    assert "holds pages already (index.html); add --overwrite to replace them" in err
    assert (out / "index.html").read_text() == "<p>the lecturer's own page</p>"


def test_a_handout_zip_is_not_replaced_without_overwrite_and_follows_the_umask(tmp_path, capsys):
    target = tmp_path / "course.zip"
    target.write_bytes(b"an older hand-out")
    err = usage_error(["course", "handout", "--root", str(ROOT), "--zip", str(target)], capsys)
    assert f"--zip {target} exists; add --overwrite to replace it" in err
    assert target.read_bytes() == b"an older hand-out"
    before = os.umask(0o022)
    try:
        assert main(["course", "handout", "--root", str(ROOT), "--zip", str(target), "--overwrite"]) == 0
    finally:
        os.umask(before)
    assert stat.S_IMODE(target.stat().st_mode) == 0o644
    assert zipfile.is_zipfile(target)


def test_a_handout_written_again_into_its_own_folder_is_named_as_a_handout(tmp_path, capsys):
    out = tmp_path / "handout"
    assert main(["course", "handout", "--root", str(ROOT), "--out", str(out)]) == 0
    err = usage_error(["course", "handout", "--root", str(ROOT), "--out", str(out)], capsys)
    assert f"--out {out} holds a course hand-out already (written earlier)" in err


def test_the_handouts_pages_link_only_to_what_the_handout_holds(tmp_path):
    import re

    out = tmp_path / "handout"
    assert main(["course", "handout", "--root", str(ROOT), "--out", str(out)]) == 0
    pages = sorted(out.rglob("*.md"))
    assert (out / "tutorials" / "README.md") in pages
    for page in pages:
        for target in re.findall(r"\]\(([^)#]+)", page.read_text(encoding="utf-8")):
            if "://" not in target:
                assert (page.parent / target).exists(), (f"{page.relative_to(out)} links to {target}, "
                                                         "not in the hand-out")
    text = (out / "tutorials" / "README.md").read_text(encoding="utf-8")
    assert "LECTURER" not in text and "source/" not in text
