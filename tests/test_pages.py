"""The course's static pages work with no network: maths as MathML, each tutorial's title, alt text on figures.

The browser test opens every page in Debian's Chromium with every request
outside the pages' folder refused; it is skipped where Chromium or
Playwright is missing, and fails on CI (as ``tests/test_browser.py``).
Screenshots land in ``$SARSP_SCREENSHOTS`` when it is set.
"""

from __future__ import annotations

import os
import re
import warnings
from pathlib import Path

import nbformat
import pytest
from bs4 import BeautifulSoup

from sarsp_edu.teaching.course import write_pages
from sarsp_edu.teaching.pages import PagesWarning, TexConversionError, tex_to_mathml

ROOT = Path(__file__).resolve().parents[1]
NOTEBOOKS = sorted((ROOT / "tutorials").glob("[0-9][0-9]_*.ipynb"))
#: nbconvert's alt text for an image it knows nothing about
NBCONVERT_ALT = "No description has been provided for this image"
#: TeX a reader must never see on a page: a command, \( \[ delimiters, a $-delimited fragment, a braced script
TEX_VISIBLE = re.compile(r"\\[A-Za-z]+|\\[()\[\]]|\$[^$\n]+\$|[_^]\{")
PNG = ("iVBORw0KGgoAAAANSUhEUgAAAAEAAAABCAYAAAAfFcSJAAAADUlEQVR42mNk+M9QDwADhgGAWjR9awAAAABJRU5ErkJggg==")


@pytest.fixture(scope="module")
def pages(tmp_path_factory):
    """The seven tutorials' pages, built once, with the warnings the build gave."""
    out = tmp_path_factory.mktemp("pages")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        write_pages(ROOT / "tutorials", out)
    return out, [str(w.message) for w in caught if issubclass(w.category, PagesWarning)]


def first_heading(notebook) -> str:
    return next(line.lstrip("#").strip() for cell in notebook.cells if cell.cell_type == "markdown"
                for line in cell.source.split("\n") if line.startswith("# "))


def metadata_alts(notebook) -> list[str]:
    """The alt texts that the notebook's image outputs carry in their metadata."""
    return [output.metadata[mimetype]["alt"] for cell in notebook.cells if cell.cell_type == "code"
            for output in cell.outputs for mimetype in ("image/png", "image/jpeg", "image/svg+xml")
            if mimetype in output.get("data", {}) and output.get("metadata", {}).get(mimetype, {}).get("alt")]


def test_every_tex_fragment_of_the_tutorials_becomes_mathml(pages):
    out, caught = pages
    assert len(NOTEBOOKS) == 7
    assert not [message for message in caught if "TeX" in message]
    for notebook in NOTEBOOKS:
        soup = BeautifulSoup((out / f"{notebook.stem}.html").read_text(encoding="utf-8"), "html.parser")
        assert soup.find_all("math"), notebook.name
        assert not soup.select(".sarsp-tex-source"), notebook.name
        assert not soup.find_all("script", src=True), f"{notebook.name} loads a script"


def test_every_local_link_of_the_pages_opens_a_file_of_the_pages_folder(pages):
    """The glossary is a page in the folder: nothing points back into the repository (was: GLOSSARY.md from
    Tutorials 1-6, broken); the students' pages do not link REPRODUCTION.md, which answers Tutorial 6's
    predictions (the lecturer's do: see below)."""
    out, caught = pages
    followed, broken = [], []
    for page in sorted(out.glob("*.html")):
        for target in re.findall(r'\b(?:href|src)="([^"]+)"', page.read_text(encoding="utf-8")):
            if re.match(r"^[a-z][a-z0-9+.-]*:", target) or target.startswith("#"):
                continue  # a web address (not followed offline), a data URI, or a place on the same page
            followed.append((page.name, target))
            if not (out / target.split("#")[0]).is_file():
                broken.append((page.name, target))
    assert broken == [] and not [m for m in caught if "does not exist beside its source" in m]
    assert ("01_tail_decay.html", "GLOSSARY.html") in followed
    assert not [link for link in followed if "REPRODUCTION" in link[1]] and not (out / "REPRODUCTION.html").exists()


def test_the_lecturers_edition_shows_every_output_its_source_stores_and_the_students_hides_the_reveals(tmp_path):
    """Session 3 can be taught from the fallback: each lecturer's page shows as many outputs as its source
    notebook stores (every reveal after its question), where the student's page shows the student notebook's."""
    import json

    write_pages(ROOT / "tutorials", tmp_path / "lecturer", edition="lecturer")
    fewer = 0
    for source in sorted((ROOT / "tutorials" / "source").glob("[0-9][0-9]_*.ipynb")):
        def outputs(path):
            return sum(len(cell.get("outputs", [])) for cell in json.loads(path.read_text(encoding="utf-8"))["cells"]
                       if cell["cell_type"] == "code")

        page = (tmp_path / "lecturer" / f"{source.stem}.html").read_text(encoding="utf-8")
        assert page.count('class="jp-OutputArea-child') == outputs(source), source.name
        fewer += outputs(ROOT / "tutorials" / source.name) < outputs(source)
    assert fewer >= 5  # the student notebooks' reveals are empty: their pages show fewer
    index = (tmp_path / "lecturer" / "index.html").read_text(encoding="utf-8")
    assert "the lecturer's edition: every reveal and answer shown" in index
    assert (tmp_path / "lecturer" / "GLOSSARY.html").is_file()  # the sources' links, written for tutorials/, work
    # REPRODUCTION.md (session 3 projects it) and the figure it shows are a page and a copy in the folder
    reproduction = (tmp_path / "lecturer" / "REPRODUCTION.html").read_text(encoding="utf-8")
    assert 'href="REPRODUCTION.html"' in index
    assert 'src="files/results/rule-study/rule-study.png"' in reproduction
    assert (tmp_path / "lecturer" / "files/results/rule-study/rule-study.png").is_file()
    with pytest.raises(ValueError, match="edition"):
        write_pages(ROOT / "tutorials", tmp_path / "x", edition="teacher")


def test_tex_to_mathml_escapes_text_and_names_what_it_cannot_convert():
    assert tex_to_mathml(r"\frac{\nu}{\nu - 2}").startswith('<math display="inline"><mrow><mfrac>')
    # a \text{} is text, never markup: latex2mathml's own convert() would hand '<b>' back unescaped
    assert "&lt;b&gt;" in tex_to_mathml(r"\text{<b>}") and "<b>" not in tex_to_mathml(r"\text{<b>}")
    assert "<munder><mo movablelimits=\"true\">lim</mo>" in tex_to_mathml(r"\lim_{x \to \infty} f", display=True)
    assert "<mo>arg</mo>" in tex_to_mathml(r"\arg\max_a f")  # rewritten to \operatorname{arg}
    assert "<mtable" in tex_to_mathml(r"\begin{aligned} a &= b \\ c &= d \end{aligned}", display=True)
    for tex, why in ((r"\foo x", r"it does not know \foo"), (r"x^{", "MissingSuperScriptOrSubscriptError"),
                     (r"a & b", "an alignment '&'"), (r"\frac{1}{2}}", "an unbalanced brace"),
                     (r"\operatorname{arg\,max}_a", "loses an operator's name")):
        with pytest.raises(TexConversionError, match=re.escape(why)) as raised:
            tex_to_mathml(tex)
        assert repr(tex) in str(raised.value)


def synthetic_tutorials(folder: Path, images) -> Path:
    """A tutorials folder holding one source and its student notebook: maths, a text/latex output, ``images``."""
    notebook = nbformat.v4.new_notebook()
    notebook.cells = [
        nbformat.v4.new_markdown_cell("# Tutorial 9: $\\nu > 2$ & more\n\nKnown $\\nu$, unknown $\\foo x$."),
        nbformat.v4.new_code_cell("show()", outputs=[
            nbformat.v4.new_output("display_data", data={"text/latex": "$\\displaystyle \\frac{1}{\\lambda^{2}}$"}),
            *[nbformat.v4.new_output("display_data", data={"image/png": PNG, "text/plain": "<Figure>"},
                                     metadata={"image/png": {"alt": alt}} if alt else {}) for alt in images]]),
    ]
    (folder / "source").mkdir(parents=True)
    for path in (folder / "source" / "09_synthetic.ipynb", folder / "09_synthetic.ipynb"):
        nbformat.write(notebook, path)
    return folder


def test_a_page_takes_its_title_alt_texts_and_maths_from_the_notebook_and_says_what_it_lacks(tmp_path):
    own = 'Two curves: "GP" < "TP", the TP\'s wider'
    tutorials = synthetic_tutorials(tmp_path / "tutorials", [own, None, ""])
    with pytest.warns(PagesWarning) as caught:
        write_pages(tutorials, tmp_path / "pages")
    messages = [str(w.message) for w in caught]
    assert any("09_synthetic.ipynb" in m and repr(r"\foo x") in m for m in messages), messages
    assert any("09_synthetic.ipynb: 2 figures carry no alt text" in m for m in messages), messages
    soup = BeautifulSoup((tmp_path / "pages" / "09_synthetic.html").read_text(encoding="utf-8"), "html.parser")
    assert soup.title.string == "Tutorial 9: ν>2 & more"
    fallback = "Figure output of cell 2 of Tutorial 9: ν>2 & more"
    assert [img["alt"] for img in soup.find_all("img")] == [own, fallback, fallback]
    assert soup.select_one(".sarsp-tex-source").get_text() == r"$\foo x$"  # shown as its TeX, never dropped
    latex = soup.select_one('[data-mime-type="text/latex"]')
    assert latex.find("math") is not None and "\\" not in latex.get_text()
    index = BeautifulSoup((tmp_path / "pages" / "index.html").read_text(encoding="utf-8"), "html.parser")
    assert [a.get_text() for a in index.find_all("a")] == ["Tutorial 9: ν>2 & more"]


@pytest.fixture(scope="module")
def browser():
    # importing test_browser skips the test, or fails it on CI, where Chromium is missing
    from .test_browser import ARGS, CHROMIUM

    playwright_api = pytest.importorskip("playwright.sync_api")
    with playwright_api.sync_playwright() as p:
        instance = p.chromium.launch(executable_path=CHROMIUM, args=ARGS)
        yield instance
        instance.close()


def test_the_pages_render_offline_with_titles_alt_texts_and_readable_figures(pages, browser):
    out, _ = pages
    inside = out.resolve().as_uri() + "/"
    refused, failed = [], []
    page = browser.new_page(viewport={"width": 1280, "height": 900})

    def only_the_folder(route):
        url = route.request.url
        if url.startswith((inside, "data:")):
            route.continue_()
        else:
            refused.append(url)
            route.abort()

    page.route("**/*", only_the_folder)
    page.on("requestfailed", lambda request: failed.append(request.url))
    shots = os.environ.get("SARSP_SCREENSHOTS")
    for path in NOTEBOOKS:
        notebook = nbformat.read(path, as_version=4)
        page.goto((out / f"{path.stem}.html").resolve().as_uri())
        page.wait_for_load_state("load")
        assert page.title() == first_heading(notebook)
        sizes = page.evaluate("Array.from(document.querySelectorAll('math')).map(m => m.getBoundingClientRect().width)")
        assert sizes and min(sizes) > 0, f"{path.name}: MathML not laid out"
        images = page.evaluate("""Array.from(document.images).map(i => ({alt: i.alt, natural: i.naturalWidth,
                                  shown: i.getBoundingClientRect().width}))""")
        stored = sum(any(key.startswith("image/") for key in output.get("data", {}))
                     for cell in notebook.cells for output in cell.get("outputs", []))
        assert len(images) >= stored, (path.name, len(images), stored)  # every stored picture is on the page
        own = metadata_alts(notebook)
        fallback = re.compile(rf"Figure output of cell \d+ of {re.escape(first_heading(notebook))}")
        for image in images:
            assert image["alt"].strip() and image["alt"] != NBCONVERT_ALT, (path.name, image)
            assert image["alt"] in own or fallback.fullmatch(image["alt"]), (path.name, image)
            # a 1,600 px dashboard picture fills the page's column on a 1280-wide screen, never a thumbnail
            assert image["shown"] >= min(image["natural"], 1000), (path.name, image)
        assert set(own) <= {image["alt"] for image in images}
        if shots:
            Path(shots).mkdir(parents=True, exist_ok=True)
            page.screenshot(path=str(Path(shots) / f"page-{path.stem}.png"), full_page=True)
        # what a reader sees, less code and the plain text it prints (where a backslash may be Python's)
        prose = page.evaluate("""(() => { document.querySelectorAll('.jp-InputArea-editor, .jp-RenderedText')
                                           .forEach(e => e.remove()); return document.body.innerText; })()""")
        assert not TEX_VISIBLE.findall(prose), f"{path.name} shows TeX: {TEX_VISIBLE.findall(prose)[:5]}"
    page.close()
    assert not refused and not failed, f"requests outside the pages' folder: {refused + failed}"
