"""The guide: the site builds in MkDocs's strict mode (a broken link, an anchor that is not
there or a page missing from the navigation fails), its generated reference pages are what the
parser and the schemas say now, and the README is a front page whose links resolve."""

from __future__ import annotations

import importlib.util
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
README = ROOT / "README.md"


def _generator():
    spec = importlib.util.spec_from_file_location(
        "generate_reference", ROOT / "docs" / "generate_reference.py"
    )
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_the_generated_reference_pages_are_up_to_date():
    generate = _generator()
    assert generate.CLI_PAGE.read_text() == generate.cli_page(), (
        "docs/reference/cli.md is stale: run docs/generate_reference.py"
    )
    assert generate.KEYS_PAGE.read_text() == generate.keys_page(), (
        "docs/reference/keys.md is stale: run docs/generate_reference.py"
    )


def test_the_reference_has_every_command_and_every_schema_key():
    """Every verb the parser has is a section of cli.md; every key of the case schema's garment
    and of the config schema's sweep is a row of keys.md, with the schema's default."""
    generate = _generator()
    page = generate.cli_page()
    for verb in ("material ingest", "body avatar", "run", "design", "sizes", "pattern"):
        assert f"## `cloth {verb}`" in page
    keys = generate.keys_page()
    assert "| `garment.reduction` |" in keys and "| `sweep.reductions` |" in keys
    assert re.search(r"\| `body\.torso\.around` \| integer \| `128` \|", keys)


def build(where: Path, site: Path) -> subprocess.CompletedProcess:
    """`make docs`'s MkDocs build, strict, of the project laid out in ``where``, into ``site``."""
    return subprocess.run(
        [sys.executable, "-m", "mkdocs", "build", "--strict", "-d", str(site)],
        cwd=where,
        capture_output=True,
        text=True,
        env={**os.environ, "NO_MKDOCS_2_WARNING": "1"},
        timeout=300,
    )


def test_the_site_builds_in_strict_mode(tmp_path):
    """`make docs`'s build: every page in the navigation, every link and anchor found."""
    done = build(ROOT, tmp_path / "site")
    assert done.returncode == 0, done.stderr[-3000:]
    for page in ("index.html", "tutorials/stocking/index.html", "reference/cli/index.html"):
        assert (tmp_path / "site" / page).is_file()


def test_a_broken_link_fails_the_strict_build(tmp_path):
    """The strict build is not vacuous: a copy of the docs with one link to a missing page
    fails, naming it."""
    import shutil

    shutil.copytree(ROOT / "docs", tmp_path / "docs")
    shutil.copy(ROOT / "mkdocs.yml", tmp_path / "mkdocs.yml")
    page = tmp_path / "docs" / "tutorials" / "index.md"
    page.write_text(page.read_text() + "\n[gone](nowhere.md)\n")
    done = build(tmp_path, tmp_path / "site")
    assert done.returncode != 0 and "nowhere.md" in done.stderr


def github_slug(heading: str) -> str:
    """The anchor GitHub gives a Markdown heading: lower case, punctuation but - and _ dropped,
    spaces to -."""
    text = re.sub(r"[^\w\- ]", "", heading.strip().lower())
    return text.replace(" ", "-")


def anchors(path: Path) -> set[str]:
    text = re.sub(r"```.*?```", "", path.read_text(), flags=re.S)
    return {github_slug(m) for m in re.findall(r"^#+ (.+)$", text, flags=re.M)}


def test_the_readme_is_a_front_page_whose_links_resolve():
    """At most 120 lines, no issue numbers, the two commands; every relative link names a file
    of the checkout, and an anchor one of its headings."""
    text = README.read_text()
    assert len(text.splitlines()) <= 120
    assert not re.search(r"\bissues? \d+", text, flags=re.I)
    assert "make run" in text and "make test" in text
    links = re.findall(r"\]\(([^)\s]+)\)", text)
    local = [link for link in links if not re.match(r"^[a-z]+:", link)]
    assert len(local) >= 10
    for link in local:
        target, _, anchor = link.partition("#")
        path = ROOT / target if target else README
        assert path.exists(), f"README links to {target}, which is not in the checkout"
        if anchor:
            assert anchor in anchors(path), f"README links to {link}: no such heading"


def test_the_link_checker_finds_a_missing_heading():
    assert github_slug("## Designing a size chart".lstrip("# ")) == "designing-a-size-chart"
    assert "designing-a-size-chart" in anchors(ROOT / "docs" / "outputs.md")
    assert "no-such-heading" not in anchors(ROOT / "docs" / "outputs.md")


@pytest.mark.parametrize("page", ["fabric", "stocking", "scan"])
def test_each_tutorial_has_commands_and_is_in_the_tutorials_index(page):
    text = (ROOT / "docs" / "tutorials" / f"{page}.md").read_text()
    assert re.search(r"```sh\n.*?\bcloth\b", text, flags=re.S)
    assert f"({page}.md)" in (ROOT / "docs" / "tutorials" / "index.md").read_text()
