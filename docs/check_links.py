#!/usr/bin/env python3
"""Checks the relative links of the README, the changelog and the docs book.

Run from anywhere: `python3 docs/check_links.py`. For every inline link or image
`[text](target)` in README.md, CHANGELOG.md and docs/**/*.md (outside code), a relative target
must exist, relative to the file it is in; an anchor (`page.md#heading`, `#heading`) must be
one of the target page's headings as GitHub spells them. docs/src/SUMMARY.md must list every
page of docs/src. Symbolic links (docs/scene-format.md) are checked through their target only.
Exits 1 and lists what fails.
"""
import os
import re
import sys
import unicodedata

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def markdown_files():
    files = [os.path.join(ROOT, name) for name in ("README.md", "CHANGELOG.md")]
    for base, dirs, names in os.walk(os.path.join(ROOT, "docs")):
        dirs[:] = [d for d in dirs if d != "book"]
        files += [os.path.join(base, n) for n in names if n.endswith(".md")]
    return [f for f in sorted(files) if os.path.isfile(f) and not os.path.islink(f)]


def strip_code(text):
    """The text with fenced blocks and code spans blanked (links there are not links)."""
    out, fenced = [], False
    for line in text.split("\n"):
        if line.lstrip().startswith("```"):
            fenced = not fenced
            out.append("")
        elif fenced:
            out.append("")
        else:
            out.append(re.sub(r"`[^`]*`", lambda m: "`" + " " * (len(m.group()) - 2) + "`", line))
    return "\n".join(out)


def slug(heading):
    """GitHub's anchor for a heading's text."""
    text = re.sub(r"!?\[([^\]]*)\]\([^)]*\)", r"\1", heading)  # links: their text
    text = text.replace("`", "").strip().lower()
    kept = []
    for ch in text:
        cat = unicodedata.category(ch)
        if ch in " -_" or cat[0] in "LN":
            kept.append(ch)
    return "".join(kept).replace(" ", "-")


ANCHORS = {}


def anchors(path):
    if path not in ANCHORS:
        seen, result = {}, set()
        text = open(path, encoding="utf-8").read()
        fenced = False
        for line in text.split("\n"):
            if line.lstrip().startswith("```"):
                fenced = not fenced
                continue
            m = None if fenced else re.match(r"^(#{1,6})\s+(.*?)\s*#*\s*$", line)
            if m:
                s = slug(m.group(2))
                n = seen.get(s, 0)
                seen[s] = n + 1
                result.add(s if n == 0 else f"{s}-{n}")
        ANCHORS[path] = result
    return ANCHORS[path]


LINK = re.compile(r"!?\[(?:[^\[\]]|\[[^\]]*\])*\]\(\s*<?([^)\s>]+)>?(?:\s+\"[^\"]*\")?\s*\)")


def check():
    failures, checked = [], 0
    for path in markdown_files():
        text = strip_code(open(path, encoding="utf-8").read())
        rel = os.path.relpath(path, ROOT)
        for lineno, line in enumerate(text.split("\n"), 1):
            for m in LINK.finditer(line):
                target = m.group(1)
                if re.match(r"^[a-z][a-z0-9+.-]*:", target):  # http:, https:, mailto:
                    continue
                checked += 1
                file_part, _, anchor = target.partition("#")
                dest = os.path.normpath(os.path.join(os.path.dirname(path), file_part)) if file_part else path
                where = f"{rel}:{lineno}: {target}"
                if not os.path.exists(dest):
                    failures.append(f"{where}: no such file")
                    continue
                if anchor and dest.endswith(".md") and anchor not in anchors(os.path.realpath(dest)):
                    failures.append(f"{where}: no heading with anchor #{anchor}")
    summary = os.path.join(ROOT, "docs", "src", "SUMMARY.md")
    if os.path.exists(summary):
        listed = set(re.findall(r"\]\(([^)#]+)\)", open(summary, encoding="utf-8").read()))
        src = os.path.dirname(summary)
        for base, _, names in os.walk(src):
            for n in names:
                page = os.path.relpath(os.path.join(base, n), src)
                if n.endswith(".md") and n != "SUMMARY.md" and page not in listed:
                    failures.append(f"docs/src/SUMMARY.md: does not list {page}")
    return checked, failures


if __name__ == "__main__":
    checked, failures = check()
    for f in failures:
        print(f)
    print(f"{checked} relative links checked, {len(failures)} failures")
    sys.exit(1 if failures else 0)
