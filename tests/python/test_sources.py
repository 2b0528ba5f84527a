"""Sources anyone can follow: no tracked file cites a document outside the repository (the team's private
reading notes and its numbered copies of the thesis and the paper), and every citation of a section of
docs/SOURCES.md names one of its headings. That file says what the thesis, the paper and every other source
are.

The turbulence seed (`rotor.seed`, `--seed`, "seed 1") is legitimate and not matched: only a seed number
written with a leading zero and three digits, the way the reading folder numbers its documents, is.
"""

import pathlib
import re
import subprocess

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
SOURCES = ROOT / "docs" / "SOURCES.md"

# Written so that this file's own text does not match them.
OUTSIDE = [
    (re.compile(r"\bseeds?[\s_-]*0\d\d", re.IGNORECASE), "a numbered document of the reading folder"),
    (re.compile(r"seeds[/]", re.IGNORECASE), "the reading folder's documents"),
    (re.compile(r"shared[/]", re.IGNORECASE), "the reading folder"),
    (re.compile(r"shared\s+seed", re.IGNORECASE), "the reading folder"),
    (re.compile(r"PARAMETERS\.md|PARAMETERS\s*§", re.IGNORECASE), "the private parameter sheet"),
    (re.compile(r"REFERENCE[-]DATA", re.IGNORECASE), "the private sheet of reference data"),
    (re.compile(r"FMI[-]NOTES", re.IGNORECASE), "the private FMI notes"),
    (re.compile(r"DEPENDENCIES\.md|DEPENDENCIES\s+A\d", re.IGNORECASE), "the private dependency notes"),
    (re.compile(r"DESIGN\.md", re.IGNORECASE), "the private design notes"),
    (re.compile(r"STYLE\.md", re.IGNORECASE), "the private style notes"),
]

CITATION = re.compile(r"SOURCES\.md\s*§\s*")
ANCHOR = re.compile(r"SOURCES\.md#([A-Za-z0-9_-]+)")
HEADING = re.compile(r"^#{1,6}\s+(.+?)\s*#*\s*$")


def tracked_text_files():
    """(path relative to the root, text) of every tracked file that is text (no NUL byte)."""
    try:
        out = subprocess.run(
            ["git", "ls-files", "-z"], cwd=ROOT, check=True, capture_output=True
        ).stdout
    except (OSError, subprocess.CalledProcessError):
        pytest.skip("not a git checkout: no tracked files to read")
    for name in out.decode().split("\0"):
        if not name:
            continue
        path = ROOT / name
        if not path.is_file():
            continue
        data = path.read_bytes()
        if b"\0" in data:
            continue
        yield name, data.decode("utf-8", errors="replace")


def headings():
    return [m.group(1) for line in SOURCES.read_text().splitlines() if (m := HEADING.match(line))]


def slug(heading):
    """GitHub's anchor of a Markdown heading."""
    s = re.sub(r"[^\w\- ]", "", heading.strip().lower())
    return s.replace(" ", "-")


def test_sources_md_exists_with_its_sections():
    assert SOURCES.is_file(), "docs/SOURCES.md is missing"
    have = set(headings())
    for required in ("Thesis", "Paper", "Public sources", "Published inputs", "Estimates"):
        assert required in have, f"docs/SOURCES.md has no section '{required}'"


def test_no_file_cites_a_document_outside_the_repository():
    hits = []
    for name, text in tracked_text_files():
        for number, line in enumerate(text.splitlines(), 1):
            for pattern, what in OUTSIDE:
                m = pattern.search(line)
                if m:
                    hits.append(f"{name}:{number}: '{m.group(0)}' ({what}): {line.strip()[:120]}")
    assert not hits, (
        "these lines cite a document users do not have; cite the origin itself (thesis Table 4.1, paper §1.3, "
        "a public report or standard, docs/SOURCES.md §Estimates):\n" + "\n".join(hits)
    )


def test_every_sources_citation_names_a_heading():
    names = sorted(headings(), key=len, reverse=True)
    anchors = {slug(h) for h in names}
    bad = []
    for name, text in tracked_text_files():
        for number, line in enumerate(text.splitlines(), 1):
            for m in CITATION.finditer(line):
                rest = line[m.end():]
                ok = any(
                    rest.startswith(h) and not (rest[len(h):len(h) + 1].isalnum()) for h in names
                )
                if not ok:
                    bad.append(f"{name}:{number}: §{rest[:40]}")
            for m in ANCHOR.finditer(line):
                if m.group(1) not in anchors:
                    bad.append(f"{name}:{number}: #{m.group(1)}")
    assert not bad, "citations of docs/SOURCES.md that name no heading of it:\n" + "\n".join(bad)
