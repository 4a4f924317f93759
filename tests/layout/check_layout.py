#!/usr/bin/python3
"""Checks the source tree's layout rules (issue 26).

1. Every author-and-year citation in the comments of lib/, formats/ and apps/ ("Hoppe 1996,
   §3", "Garland and Heckbert 1997", "Cignoni et al. 1998", "Figueroa, "Title", 1995") names
   a work that docs/references.md lists, and the citing file is among that work's files;
   a file listed for a work must exist and cite it.
2. No source file in lib/ or formats/ is over 1,000 lines, none in apps/ over 400.
3. Every folder under lib/src/ has a README.md.

A work is known by its first author's surname and its year: "Schroeder, Zarge and Lorensen
1992" and "Schroeder 1992" are the same work, as are "Cignoni et al. 1998" and "Cignoni,
Rocchini and Scopigno 1998". docs/references.md gives each work a heading that cites it
("### Garland and Heckbert 1997") and a "- **Files**:" line of backquoted paths.

Usage: check_layout.py [--root DIR] [--list] [--update] [selftest] [citations] [sizes] [readmes]
  CHECKS    which checks to run (all by default); selftest runs the citation finder on
            cases it must get right, citations and readmes are rules 1 and 3, sizes rule 2
  --root    the source tree (by default the one this script is in)
  --list    print every citation found (file:line: work: the text matched), then check
  --update  rewrite the Files lines of docs/references.md from the comments (after moving or
            splitting files); a work the file does not list still fails: write its entry.
Exit status 0 when every rule holds, 1 otherwise (each failure on one line), 2 on bad usage.
"""
import os
import re
import sys
import tempfile

SOURCE_SUFFIXES = (".h", ".hpp", ".cpp", ".cc", ".c", ".inl")
CITING_ROOTS = ("lib", "formats", "apps")
LINE_LIMITS = {"lib": 1000, "formats": 1000, "apps": 400}
REFERENCES = os.path.join("docs", "references.md")

# Capitalised words that can stand before a year without naming an author: sentence
# openers, months, venues, products.
NOT_AUTHORS = {
    "A", "An", "And", "As", "At", "Before", "Between", "By", "Circa", "Copyright", "Debian",
    "Draco", "Eurographics", "Format", "From", "Graphics", "Ieee", "In", "Its", "January",
    "February", "March", "April", "May", "June", "July", "August", "September", "October",
    "November", "December", "Of", "On", "Proceedings", "Proc", "See", "Siggraph", "Since",
    "The", "Then", "To", "Until", "Up", "Version", "Visualization", "Year", "Years", "Zstd",
}
NAME = r"(?:[A-ZÀ-Þ][a-zß-ÿ][^\W\d_]*(?:['’-][A-ZÀ-Þ]?[^\W\d_]+)*)"
AUTHORS = (rf"(?P<authors>{NAME}(?:,\s+{NAME})*(?:,?\s+and\s+{NAME})?"
           rf"|{NAME}\s+et\s+al\.)")
YEAR = r"(?:19[7-9]\d|20[0-2]\d)"
# "Hoppe 1996", "Schroeder 1992/1997", "Schroeder 1992, 1997", "Hoppe 1996's"; a year glued
# to digits, a dot or a dash ("1996.5", "2008-11") is not one.
YEARS = rf"(?P<years>{YEAR}(?:(?:/|,\s*|\s+and\s+){YEAR}(?![\d]))*)(?![\d.\-]\d|\d)"
CITATION = re.compile(rf"(?<![\w.'’-]){AUTHORS}\s+{YEARS}")
# Figueroa, "When is double rounding innocuous?", 1995
TITLED = re.compile(rf"(?<![\w.'’-]){AUTHORS},\s+\"[^\"]{{3,200}}\",?\s+{YEARS}")


def comments(text):
    """Yields each comment block as a list of (line number, text) pieces: a run of //
    comments on consecutive lines is one block, as is each /* */ comment; string and
    character literals are skipped."""
    i, n, line = 0, len(text), 1
    block, last_line = [], -2
    while i < n:
        c = text[i]
        if c == "\n":
            line += 1
            i += 1
        elif text.startswith("//", i):
            end = text.find("\n", i)
            end = n if end < 0 else end
            if line != last_line + 1 and block:
                yield block
                block = []
            block.append((line, text[i + 2:end].lstrip("/!").strip()))
            last_line = line
            i = end
        elif text.startswith("/*", i):
            end = text.find("*/", i + 2)
            end = n if end < 0 else end
            body = text[i + 2:end].split("\n")
            yield [(line + k, l.strip().lstrip("*").strip()) for k, l in enumerate(body)]
            line += len(body) - 1
            i = end + 2
        elif c == '"' or (c == "'" and not (i and text[i - 1].isalnum())):
            # A string or character literal (not a digit separator, 1'000; raw strings are
            # rare enough here to ignore).
            j = i + 1
            while j < n and text[j] != c and text[j] != "\n":
                j += 2 if text[j] == "\\" else 1
            i = j + 1
        else:
            i += 1
    if block:
        yield block


def first_author(authors):
    return re.match(NAME, authors).group(0)


def citations(text):
    """Yields (line, work key, matched text) for the citations in one file's comments, once
    per work and comment block, at the line where the citation starts."""
    for block in comments(text):
        joined, starts = "", []
        for line, piece in block:
            starts.append((len(joined), line))
            joined += piece + " "
        found = []
        for pattern in (CITATION, TITLED):
            for m in pattern.finditer(joined):
                # "Since Garland and Heckbert 1997": drop leading words that are not names.
                words = re.findall(NAME, m.group("authors"))
                while words and words[0] in NOT_AUTHORS:
                    words.pop(0)
                if not words:
                    continue
                line = max(l for offset, l in starts if offset <= m.start())
                for year in re.findall(YEAR, m.group("years")):
                    found.append((m.start(), line, f"{words[0]} {year}", " ".join(m.group(0).split())))
        seen = set()
        for start, line, key, matched in sorted(found):
            if key not in seen:
                seen.add(key)
                yield line, key, matched


def source_files(root, top):
    for folder, dirs, files in os.walk(os.path.join(root, top)):
        dirs.sort()
        for name in sorted(files):
            if name.endswith(SOURCE_SUFFIXES):
                yield os.path.relpath(os.path.join(folder, name), root)


class Entry:
    """One work's entry in docs/references.md: its heading, the work keys the heading cites
    ("### Khronos 2017/2021" stands for Khronos 2017 and Khronos 2021), its Files and the
    line those are on."""

    def __init__(self, heading, keys):
        self.heading, self.keys, self.files, self.files_line = heading, keys, [], None


def read_references(path):
    """Returns {work key: Entry}, the file's lines and the headings that repeat a work."""
    works, lines, duplicates = {}, [], []
    if not os.path.exists(path):
        return works, lines, duplicates
    with open(path, encoding="utf-8") as f:
        lines = f.read().split("\n")
    entry = None
    for number, text in enumerate(lines):
        if text.startswith("#"):
            m = CITATION.search(text[4:]) if text.startswith("### ") else None
            entry = None
            if m:
                author = first_author(m.group("authors"))
                keys = [f"{author} {year}" for year in re.findall(YEAR, m.group("years"))]
                entry = Entry(text[4:].strip(), keys)
                for key in keys:
                    if key in works:
                        duplicates.append(f"{REFERENCES}:{number + 1}: a second entry for {key}")
                    works[key] = entry
        elif entry and re.match(r"\s*-\s*\*\*Files\*\*:", text):
            entry.files, entry.files_line = re.findall(r"`([^`]+)`", text), number
    return works, lines, duplicates


def check_citations(root, options, failures):
    cited = {}  # work key -> {file: (line, matched)}
    for top in CITING_ROOTS:
        for path in source_files(root, top):
            with open(os.path.join(root, path), encoding="utf-8", errors="replace") as f:
                text = f.read()
            for line, key, matched in citations(text):
                cited.setdefault(key, {}).setdefault(path, (line, matched))
                if "--list" in options:
                    print(f"{path}:{line}: {key}: {matched}")
    references = os.path.join(root, REFERENCES)
    works, lines, duplicates = read_references(references)
    if not lines:
        failures.append(f"{REFERENCES}: missing")
    failures.extend(duplicates)
    entries = list({id(e): e for e in works.values()}.values())
    citing = lambda entry: {p for key in entry.keys for p in cited.get(key, {})}
    if "--update" in options and lines:
        for entry in entries:
            if entry.files_line is not None and citing(entry):
                lines[entry.files_line] = "- **Files**: " + ", ".join(f"`{p}`" for p in sorted(citing(entry)))
        with open(references, "w", encoding="utf-8") as f:
            f.write("\n".join(lines))
        works, lines, duplicates = read_references(references)
        entries = list({id(e): e for e in works.values()}.values())
    for key in sorted(cited):
        for path, (line, matched) in sorted(cited[key].items()):
            if key not in works:
                failures.append(f"{path}:{line}: cites {key} (\"{matched}\"), which {REFERENCES} does not list "
                                f"(give it an entry: heading, full citation, what pm took, Files)")
            elif path not in works[key].files:
                failures.append(f"{path}:{line}: cites {key} (\"{matched}\"), but {REFERENCES} does not list "
                                f"this file among its files (check_layout.py --update rewrites them)")
    for entry in entries:
        if entry.files_line is None:
            failures.append(f"{REFERENCES}: {entry.heading} has no '- **Files**:' line")
        for path in entry.files:
            if path not in citing(entry):
                failures.append(f"{REFERENCES}: {entry.heading} lists {path}, whose comments do not cite it "
                                f"(check_layout.py --update rewrites the Files lines)")
    files_citing = len({p for files in cited.values() for p in files})
    return f"{len(cited)} works cited in {files_citing} files"


def check_sizes(root, options, failures):
    checked = 0
    for top, limit in LINE_LIMITS.items():
        for path in source_files(root, top):
            checked += 1
            with open(os.path.join(root, path), "rb") as f:
                count = f.read().count(b"\n")
            if count > limit:
                failures.append(f"{path}: {count} lines, over the {limit} a source file in {top}/ may have")
    return f"{checked} source files sized"


def check_readmes(root, options, failures):
    folders = 0
    for folder, dirs, files in os.walk(os.path.join(root, "lib", "src")):
        dirs.sort()
        folders += 1
        if "README.md" not in files:
            failures.append(f"{os.path.relpath(folder, root)}/: no README.md "
                            f"(a paragraph: what it does, its papers, what it may include)")
    return f"{folders} folders of lib/src"


# The citation finder on cases it must get right: (source text, works it must find).
SELF_TEST = [
    ("// Hoppe 1996, §3: wedges", ["Hoppe 1996"]),
    ("// Garland and Heckbert 1997's quadrics", ["Garland 1997"]),
    ("// (Cignoni et al. 1998)", ["Cignoni 1998"]),
    ("// Klein, Liebich and Straßer 1996", ["Klein 1996"]),
    ("// Taubin, Guéziec, Horn and Lazarus 1998, §5", ["Taubin 1998"]),
    ("// El-Sana and Varshney 1999, §3", ["El-Sana 1999"]),
    ("// Schroeder 1992/1997 and Schroeder 1992, 1997", ["Schroeder 1992", "Schroeder 1997"]),
    ("// the link condition (Dey, Edelsbrunner, Guha and\n// Nekhayev 1999, §2)", ["Dey 1999"]),
    ("/* Marpe et al.\n * 2003, §III.A */", ["Marpe 2003"]),
    ("// Since Garland and Heckbert 1997, see Hoppe et al. 1993", ["Garland 1997", "Hoppe 1993"]),
    ('// (Figueroa, "When is double rounding innocuous?", 1995)', ["Figueroa 1995"]),
    # Not citations: versions, dates, venues, standards, sentence openers, strings, code.
    ("// C++17, zstd 1.5.4, Debian 12, OpenMesh 9, format 2.4, IEEE 754-2008", []),
    ("// (CGI 2003), SIGGRAPH 1996, In 1996, Since 2019, November 2026, Copyright 2024", []),
    ("// [31, 2017] / 2048; 1996.5; 2008-11-02", []),
    ('const char* s = "Hoppe 1996"; int Hoppe = 1996;', []),
    ("int n = 1'000;  // Hoppe 1996", ["Hoppe 1996"]),
    ("// Hoppe\n\nint x;  // 1996", []),
]


# A small tree that breaks each rule once, and the failures the checks must report on it.
SELF_TEST_TREE = {
    "lib/src/core/README.md": "core\n",
    "lib/src/core/a.cpp": "// Hoppe 1996, §3, and Smith and Jones 2011.\nint a;\n",
    "lib/src/core/b.cpp": "// Hoppe 1996.\n" + "int b;\n" * 1000,
    "lib/src/bare/c.h": "// nothing cited\n",
    "apps/d.cpp": "int d;\n" * 401,
    "docs/references.md": "### Hoppe 1996\n- **Files**: `lib/src/core/a.cpp`, `apps/d.cpp`\n",
}
SELF_TEST_FAILURES = [
    "lib/src/core/a.cpp:1: cites Smith 2011",
    "lib/src/core/b.cpp:1: cites Hoppe 1996",
    "docs/references.md: Hoppe 1996 lists apps/d.cpp",
    "lib/src/core/b.cpp: 1001 lines, over the 1000",
    "apps/d.cpp: 401 lines, over the 400",
    "lib/src/bare/: no README.md",
    "lib/src/: no README.md",
]


def check_selftest(root, options, failures):
    for text, expected in SELF_TEST:
        found = sorted({key for line, key, matched in citations(text)})
        if found != sorted(expected):
            failures.append(f"check_layout.py self-test: {text!r} gives {found}, not {sorted(expected)}")
    with tempfile.TemporaryDirectory() as tree:
        for path, text in SELF_TEST_TREE.items():
            os.makedirs(os.path.dirname(os.path.join(tree, path)), exist_ok=True)
            with open(os.path.join(tree, path), "w", encoding="utf-8") as f:
                f.write(text)
        reported = []
        for name in ("citations", "sizes", "readmes"):
            CHECKS[name](tree, set(), reported)
    for expected in SELF_TEST_FAILURES:
        if sum(r.startswith(expected) for r in reported) != 1:
            failures.append(f"check_layout.py self-test: the broken tree does not report '{expected}' once")
    if len(reported) != len(SELF_TEST_FAILURES):
        failures.append(f"check_layout.py self-test: the broken tree reports {reported}")
    return f"{len(SELF_TEST)} self-test cases and a broken tree"


CHECKS = {"selftest": check_selftest, "citations": check_citations, "sizes": check_sizes,
          "readmes": check_readmes}


def main(argv):
    options, checks, root = set(), [], None
    args = iter(argv)
    for arg in args:
        if arg == "--root":
            root = next(args, None)
        elif arg in ("--list", "--update"):
            options.add(arg)
        elif arg in CHECKS:
            checks.append(arg)
        else:
            print(f"check_layout.py: unknown argument {arg!r}\n" + __doc__.split("Usage: ")[1], file=sys.stderr)
            return 2
    if root is None:
        root = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
    root = os.path.abspath(root)
    failures, summary = [], []
    for name in checks or list(CHECKS):
        summary.append(CHECKS[name](root, options, failures))
    for failure in failures:
        print(failure)
    print(f"check_layout: {'; '.join(summary)}; {len(failures)} failure{'' if len(failures) == 1 else 's'}",
          file=sys.stderr)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
