"""Static HTML pages of the student notebooks that work with no network (``sarsp-edu course pages``).

A page is nbconvert's ``lab`` export of a student notebook with three
changes, so that it can be opened from a USB stick on a projector's laptop:

* **maths as MathML.**  Every TeX fragment of the Markdown cells (``$...$``,
  ``$$...$$``, ``\\begin{...}`` environments) and of the ``text/latex`` and
  ``text/markdown`` outputs is converted when the page is built, by
  latex2mathml, into MathML, which browsers render natively (MathML Core:
  Chromium and Edge since 109, Firefox, Safari); the page loads no MathJax
  and no script from a CDN.  A fragment that cannot be converted is kept as
  its TeX source and the build warns, naming the notebook and the fragment.
* **a title:** the notebook's first heading, not nbconvert's "Notebook".
* **alt text on every figure:** an image output's alt text is read from its
  metadata, ``output.metadata["image/png"]["alt"]`` (nbformat's
  per-mimetype metadata); a figure without one is described by where it
  comes from, and the build warns once per page with the count.
"""

from __future__ import annotations

import functools
import html
import re
import warnings
from pathlib import Path

from .layout import sources, student_notebooks

__all__ = ["ALT_KEY", "PagesWarning", "TexConversionError", "tex_to_mathml", "page_title", "describe_figures",
           "write_pages"]

#: what the index's heading adds for each edition
EDITION_TITLES = {"student": "", "lecturer": " (the lecturer's edition: every reveal and answer shown)"}
#: the key of an image output's alt text in its per-mimetype metadata: ``output.metadata[mimetype][ALT_KEY]``
ALT_KEY = "alt"
#: the image mimetypes nbconvert shows as an ``<img>``, each of which gets alt text
IMAGE_MIMETYPES = ("image/png", "image/jpeg", "image/svg+xml")
#: TeX that latex2mathml does not know, rewritten to TeX that means the same and that it does know
TEX_REWRITES = (
    (re.compile(r"\\arg(?![A-Za-z])"), r"\\operatorname{arg}"),
    (re.compile(r"\\operatorname\*"), r"\\operatorname"),
    (re.compile(r"\\(begin|end)\{aligned\}"), r"\\\1{align*}"),
    (re.compile(r"\\begin\{(?:gathered|gather\*?)\}"), r"\\begin{array}{c}"),
    (re.compile(r"\\end\{(?:gathered|gather\*?)\}"), r"\\end{array}"),
)
#: what in latex2mathml's MathML betrays TeX it did not understand: a command kept as text (``<mi>\\foo</mi>``),
#: an alignment ``&`` outside a table, an operator lost (``<mo />``, from ``\\operatorname{arg\\,max}``), a brace
#: kept as a character (unbalanced: latex2mathml writes an escaped ``\\{`` as ``&#x0007B;``)
UNCONVERTED = re.compile(r">\\[A-Za-z]+|>&amp;<|<mo />|>[{}]<")
#: operators whose limits go under them in display maths (latex2mathml puts them as subscripts)
LIMIT_OPERATORS = frozenset({"lim", "liminf", "limsup", "max", "min", "sup", "inf", "det", "gcd", "Pr", "argmax",
                             "argmin"})
_ESCAPED_ENTITY = re.compile(r"&amp;(#x[0-9A-Fa-f]+;)")
#: the page template: nbconvert's lab page without require.js and MathJax (both from a CDN), with alt text on images
PAGE_TEMPLATE_NAME = "sarsp_edu_page.html.j2"
PAGE_TEMPLATE = """{%- extends 'index.html.j2' -%}
{%- block html_head_js_requirejs -%}{%- endblock html_head_js_requirejs -%}
{%- block html_head_js_mathjax -%}{%- endblock html_head_js_mathjax -%}
{% block extra_css %}
<style type="text/css">
math { font-family: "Latin Modern Math", "STIX Two Math", "Cambria Math", "DejaVu Math TeX Gyre", math; }
math[display="block"] { margin: 0.6em 0; }
.jp-RenderedMarkdown math, .jp-RenderedLatex math { font-size: 1.1em; }
.sarsp-tex-source { color: #b00020; }
</style>
{% endblock extra_css %}
{% block data_png scoped %}{{ super() | replace("<img ", "<img alt=\\"" ~ (output | get_metadata('alt', 'image/png')
   | escape_html) ~ "\\" ", 1) }}{% endblock data_png %}
{% block data_jpg scoped %}{{ super() | replace("<img ", "<img alt=\\"" ~ (output | get_metadata('alt', 'image/jpeg')
   | escape_html) ~ "\\" ", 1) }}{% endblock data_jpg %}
{% block data_svg scoped %}{{ super() | replace("<img ", "<img alt=\\"" ~ (output | get_metadata('alt', 'image/svg+xml')
   | escape_html) ~ "\\" ", 1) }}{% endblock data_svg %}
{% block data_latex scoped %}
<div class="jp-RenderedLatex jp-OutputArea-output {{ extra_class }}" data-mime-type="text/latex">
{{ output.data['text/latex'] | markdown2html }}
</div>
{%- endblock data_latex %}
"""


class PagesWarning(UserWarning):
    """Something on a page is not as a reader needs it: TeX shown as source, a figure without its own alt text."""


class TexConversionError(ValueError):
    """A TeX fragment that latex2mathml cannot convert into MathML."""


def tex_to_mathml(tex: str, display: bool = False) -> str:
    """The MathML of a TeX fragment (given without its ``$`` delimiters), as a browser renders it with no script.

    Parameters
    ----------
    tex : str
        The TeX, e.g. ``r"\\frac{\\nu}{\\nu - 2}"``; environments
        (``\\begin{align*} ... \\end{align*}``) included.
    display : bool
        Display maths (a block of its own, ``$$...$$``) rather than inline.

    Raises :class:`TexConversionError` naming the fragment where latex2mathml
    fails, or where its MathML shows that it did not understand the TeX
    (:data:`UNCONVERTED`: a command it does not know kept as text, a stray
    ``&`` or brace, a lost operator name).

    Examples
    --------
    >>> tex_to_mathml(r"\\nu > 2")
    '<math display="inline"><mrow><mi>&#x003BD;</mi><mo>&#x0003E;</mo><mn>2</mn></mrow></math>'
    """
    from xml.etree.ElementTree import tostring

    from latex2mathml.converter import convert_to_element

    rewritten = tex
    for pattern, replacement in TEX_REWRITES:
        rewritten = pattern.sub(replacement, rewritten)
    try:
        element = convert_to_element(rewritten, display="block" if display else "inline")
    except Exception as exc:  # noqa: BLE001 - latex2mathml raises its own exceptions, and others on broken TeX
        raise TexConversionError(f"latex2mathml cannot convert the TeX {tex!r} ({type(exc).__name__})") from None
    element.attrib.pop("xmlns", None)  # HTML puts <math> in MathML's namespace by itself
    if display:
        _limits_under(element)
    # latex2mathml stores characters as entities ('&#x003BD;') in the text, which tostring escapes once more;
    # its own convert() then unescapes everything, '<' of a \text{} included: only those entities are restored
    mathml = _ESCAPED_ENTITY.sub(r"&\1", tostring(element, encoding="unicode"))
    unknown = UNCONVERTED.search(mathml)
    if unknown:
        found = unknown.group(0)
        why = ("an alignment '&' outside an environment it knows" if "&" in found else
               "it loses an operator's name" if found == "<mo />" else
               "an unbalanced brace" if found[1] in "{}" else f"it does not know {found[1:]}")
        raise TexConversionError(f"latex2mathml cannot convert the TeX {tex!r} ({why})")
    return mathml


def _limits_under(element) -> None:
    """``\\lim_{x}`` in display maths as TeX sets it, the limit under the operator (MathML Core's movablelimits)."""
    for node in element.iter():
        if node.tag in ("msub", "msubsup") and len(node) and node[0].tag == "mo" and node[0].text in LIMIT_OPERATORS:
            node.tag = "munder" if node.tag == "msub" else "munderover"
            node[0].set("movablelimits", "true")


class _Maths:
    """The TeX fragments of one page turned into MathML: how many were, and which were not."""

    def __init__(self):
        self.converted, self.failed = 0, []

    def __call__(self, tex: str, display: bool, source: str) -> str:
        try:
            mathml = tex_to_mathml(tex, display)
        except TexConversionError as exc:
            self.failed.append(str(exc))
            return f'<code class="sarsp-tex-source">{html.escape(source)}</code>'
        self.converted += 1
        return mathml


@functools.cache
def _nbconvert():
    """nbconvert's Markdown parser, and a renderer and a lab HTML exporter that write MathML where nbconvert writes
    TeX for MathJax (nbconvert is imported here: the pages need it, the package's core does not)."""
    import jinja2
    from nbconvert import HTMLExporter
    from nbconvert.filters.markdown_mistune import IPythonRenderer, MarkdownWithMath

    class MathMLRenderer(IPythonRenderer):
        """nbconvert's Markdown renderer; its maths goes through ``maths`` (a :class:`_Maths`)."""

        def __init__(self, maths: _Maths, **options):
            super().__init__(**options)
            self.maths = maths

        def inline_math(self, body: str) -> str:
            return self.maths(body, False, f"${body}$")

        def block_math(self, body: str) -> str:
            return self.maths(body, True, f"$${body}$$")

        def latex_environment(self, name: str, body: str) -> str:
            tex = f"\\begin{{{name}}}{body}\\end{{{name}}}"
            return self.maths(tex, True, tex)

    class PageExporter(HTMLExporter):
        """The lab exporter with :data:`PAGE_TEMPLATE`, whose Markdown (cells, text/markdown and text/latex
        outputs) goes through :class:`MathMLRenderer`."""

        def __init__(self, maths: _Maths):
            super().__init__(template_name="lab", template_file=PAGE_TEMPLATE_NAME,
                             extra_loaders=[jinja2.DictLoader({PAGE_TEMPLATE_NAME: PAGE_TEMPLATE})])
            self.maths = maths

        @jinja2.pass_context
        def markdown2html(self, context, source):
            """As HTMLExporter.markdown2html, with :class:`MathMLRenderer`."""
            cell = context.get("cell", {})
            renderer = MathMLRenderer(
                self.maths, escape=False, attachments=cell.get("attachments", {}), embed_images=self.embed_images,
                path=context.get("resources", {}).get("metadata", {}).get("path", ""),
                anchor_link_text=self.anchor_link_text, exclude_anchor_links=self.exclude_anchor_links,
                **self.lexer_options)
            return MarkdownWithMath(renderer=renderer).render(source)

    return MarkdownWithMath, MathMLRenderer, PageExporter


def page_title(notebook, fallback: str) -> str:
    """The text of a notebook's first Markdown heading (its maths as the characters its MathML shows), else
    ``fallback``.

    Parameters
    ----------
    notebook : nbformat.NotebookNode
    fallback : str
        The title when no Markdown cell has a heading, or the heading has no text.
    """
    for cell in notebook.cells:
        if cell.cell_type != "markdown":
            continue
        heading = next((line for line in cell.source.split("\n") if re.match(r"#{1,6}\s", line)), None)
        if heading is not None:
            markdown, renderer, _ = _nbconvert()
            rendered = markdown(renderer=renderer(_Maths(), escape=False, exclude_anchor_links=True)).render(heading)
            text = html.unescape(re.sub(r"<[^>]+>", "", rendered))
            return re.sub(r"\s+", " ", text).strip() or fallback
    return fallback


def describe_figures(notebook, title: str) -> int:
    """Give every image output without alt text in its metadata one that says where it comes from, in place.

    Returns how many images had none.

    Parameters
    ----------
    notebook : nbformat.NotebookNode
        Changed in place.
    title : str
        The page's title, named in each alt text given ('Figure output of cell N of TITLE').
    """
    missing = 0
    for number, cell in enumerate(notebook.cells, start=1):
        for output in cell.get("outputs", []) if cell.cell_type == "code" else []:
            for mimetype in IMAGE_MIMETYPES:
                if mimetype not in output.get("data", {}):
                    continue
                metadata = output.setdefault("metadata", {}).setdefault(mimetype, {})
                alt = metadata.get(ALT_KEY)
                if not isinstance(alt, str) or not alt.strip():
                    metadata[ALT_KEY] = f"Figure output of cell {number} of {title}"
                    missing += 1
    return missing


class _LocalLinks:
    """The pages' links to files beside their notebooks, made to work in the pages' folder, offline.

    A link to a tutorial's notebook goes to its page; to a Markdown file (the glossary, ``REPRODUCTION.md``) to
    that file rendered as a page of its own (its own local links followed in turn); to any other file (a
    figure) to a copy under ``files/``.  A link to nothing is said (:class:`PagesWarning`) and left as it is.
    """

    HREF = re.compile(r'(?P<attr>\b(?:href|src))="(?P<target>[^"#:]+?)(?P<anchor>#[^"]*)?"')

    def __init__(self, out: Path, notebooks, root: Path):
        self.out, self.root = out, root
        self.pages = {Path(path).stem for path in notebooks}
        self.documents = {}  # a Markdown file's resolved path -> its page's name
        self.written = set()
        self.titles = []  # (page name, title) of each document written

    def rewrite(self, body: str, folder: Path) -> str:
        """``body`` with each local ``href``/``src`` (relative to ``folder``) pointing into the pages' folder."""
        def local(match):
            target, anchor = match["target"], match["anchor"] or ""
            if target.startswith(("/", "data")) or not target.strip():
                return match[0]
            path = (folder / target).resolve()
            if path.suffix == ".ipynb" and path.stem in self.pages:
                new = f"{path.stem}.html"
            elif path.suffix == ".md" and path.is_file():
                new = self.documents.setdefault(path, f"{path.stem}.html")
            elif path.is_file():
                new = self._copy(path)
            else:
                warnings.warn(f"a page links to {target}, which does not exist beside its source ({folder}); the "
                              "link is left as it is", PagesWarning, stacklevel=3)
                return match[0]
            return f'{match["attr"]}="{html.escape(new)}{anchor}"'
        return self.HREF.sub(local, body)

    def _copy(self, path: Path) -> str:
        from .._internal.io import atomic_write_bytes

        try:  # its path in the repository (results/rule-study/rule-study.png), so that no two copies collide
            name = (Path("files") / path.relative_to(self.root)).as_posix()
        except ValueError:
            name = f"files/{path.name}"
        (self.out / name).parent.mkdir(parents=True, exist_ok=True)
        atomic_write_bytes(self.out / name, path.read_bytes())
        return name

    def write_documents(self) -> None:
        """Render every Markdown file linked to (and those they link to) as a page of its own."""
        from .._internal.io import atomic_write_text

        markdown, renderer, _ = _nbconvert()
        while set(self.documents) - self.written:
            path = sorted(set(self.documents) - self.written)[0]
            self.written.add(path)
            source = path.read_text(encoding="utf-8")
            heading = next((line.lstrip("#").strip() for line in source.split("\n") if line.startswith("# ")),
                           path.name)
            body = markdown(renderer=renderer(_Maths(), escape=False)).render(source)
            self.titles.append((self.documents[path], heading))
            atomic_write_text(self.out / self.documents[path], (
                "<!DOCTYPE html>\n<html lang='en'><head><meta charset='utf-8'>"
                f"<title>{html.escape(heading)}</title>"
                "<style>body{font:20px/1.5 sans-serif;max-width:50em;margin:2em auto}"
                "table{border-collapse:collapse}td,th{border:1px solid #999;padding:0 .4em}"
                "img{max-width:100%}</style></head><body>"
                + self.rewrite(body, path.parent) + "</body></html>\n"))


def write_pages(tutorials="tutorials", out="pages", edition: str = "student") -> Path:
    """Static HTML pages of the student notebooks (or the sources), with every output and dashboard picture.

    A lecturer can project them with no Python running and no network: the
    dashboards show the picture their outputs carry (the notebooks store no
    widget state), the maths is MathML written into the page when it is
    built (no MathJax, no CDN), and the pages load nothing from outside
    their folder.  Each page is titled with its notebook's first heading;
    each figure's alt text comes from its output's metadata,
    ``output.metadata["image/png"]["alt"]``.

    Warns (:class:`PagesWarning`) once per page where a TeX fragment cannot
    be converted (naming the notebook and the fragment; the page shows the
    TeX) or where figures carry no alt text of their own (with the count).

    Returns the index page.

    Parameters
    ----------
    tutorials : path-like, default "tutorials"
        The tutorials folder, whose student notebooks must have been written.
    out : path-like, default "pages"
        The folder the pages and ``index.html`` are written to (made if missing).
    edition : {"student", "lecturer"}, default "student"
        ``"student"``: the student notebooks, whose reveals are empty until a
        student runs them.  ``"lecturer"``: the source notebooks, every reveal
        shown after its question and every answer in, and ``REPRODUCTION.md``
        as a page of its own (the fallback to teach from when no kernel runs;
        never for students).
    """
    import nbformat

    from .._internal.io import atomic_write_text
    from .._internal.validation import check_choice

    check_choice("edition", edition, ("student", "lecturer"))
    tutorials, out = Path(tutorials), Path(out)
    notebooks = student_notebooks(tutorials) if edition == "student" else sources(tutorials)
    page_exporter = _nbconvert()[2]
    out.mkdir(parents=True, exist_ok=True)
    entries = []
    links = _LocalLinks(out, notebooks, tutorials.resolve().parent)
    for path in notebooks:
        notebook = nbformat.read(path, as_version=4)
        notebook.metadata.pop("widgets", None)  # the dashboards' pictures, not a widget loader from the network
        title = page_title(notebook, path.stem)
        notebook.metadata["title"] = title
        missing = describe_figures(notebook, title)
        maths = _Maths()
        body, _ = page_exporter(maths).from_notebook_node(notebook)
        page = out / f"{path.stem}.html"
        atomic_write_text(page, links.rewrite(body, path.parent))  # a source's links lead from tutorials/source/
        for problem in maths.failed:
            warnings.warn(f"{path.name}: {problem}; the page shows it as TeX source", PagesWarning, stacklevel=2)
        if missing:
            warnings.warn(f"{path.name}: {missing} figure{'s carry' if missing > 1 else ' carries'} no alt text in "
                          f"the output's metadata (output.metadata[mimetype]['{ALT_KEY}']); the page describes "
                          f"{'them' if missing > 1 else 'it'} only as 'Figure output of cell N'", PagesWarning,
                          stacklevel=2)
        entries.append(f'<li><a href="{page.name}">{html.escape(title)}</a></li>')
    report = links.root / "REPRODUCTION.md"  # session 3 projects it; it answers Tutorial 6: lecturers' only
    if edition == "lecturer" and report.is_file():
        links.documents.setdefault(report.resolve(), "REPRODUCTION.html")
    links.write_documents()
    documents = "".join(f'<li><a href="{html.escape(name)}">{html.escape(title)}</a></li>'
                        for name, title in links.titles)
    index = out / "index.html"
    atomic_write_text(index, "<!DOCTYPE html>\n<html lang='en'><head><meta charset='utf-8'>"
                      "<title>sarsp_edu tutorials</title>"
                      "<style>body{font:20px/1.5 sans-serif;max-width:50em;margin:2em auto}</style></head><body>"
                      f"<h1>sarsp_edu: the tutorials, as static pages{EDITION_TITLES[edition]}</h1>"
                      "<ol>" + "".join(entries) + "</ol>"
                      + (f"<p>The documents they link to:</p><ul>{documents}</ul>" if documents else "") +
                      "<p>Every output and dashboard picture is stored in the pages, and the maths is written in "
                      "them as MathML: no Python runs and no network is needed.</p></body></html>\n")
    return index
