#!/usr/bin/env python3
"""Rewrite the "spec §N" citations in Rust comments to the docs/ page that holds the derivation.

Convention (issue 23, item 4): a citation of the external math specs (`mdr.md`, `sam.md`, which
users of the repository do not have) becomes a repository-relative link to a heading of
docs/theory-mdr.md or docs/theory-sam.md, written as

    docs/theory-sam.md#stick-slip-solver-and-force-control

(the GitHub anchor of the heading; no "§" is emitted, so the rewrite is idempotent). Examples:

    (spec §4.3)            -> (docs/theory-sam.md#stick-slip-solver-and-force-control)
    spec `mdr.md` §0.3     -> docs/theory-mdr.md#power-sums
    spec §7 P3             -> docs/theory-mdr.md#p3-one-sided-differences-at-the-edge
    spec §5.3–5.5          -> docs/theory-sam.md#mirror-image-and-correction-pressure to #layered-operators
    spec §1, §4.2          -> docs/theory-mdr.md#profile-transform, docs/theory-mdr.md#graded-constant-cn
    spec §7 P4, P5         -> docs/theory-mdr.md#p4-the-origin, #p5-conical-profiles
    spec §5's edge rule    -> the edge rule of docs/theory-mdr.md#fretting-wear
    spec `sam.md`          -> docs/theory-sam.md

Which document an unqualified "§N" means is decided, in this order, by an explicit qualifier
(`mdr.md`, `sam.md`), by the section existing in only one document (e.g. §0.2, §7 P9 → mdr;
§5.4, §7.3, §8.11 → sam), by the crate (crates/mdr, crates/fretting → mdr; crates/sam → sam;
crates/numerics by module: conv1d, power_sum, grid, diff, quad, special → mdr; fft*, conv2d,
layered, circulant, krylov, anderson, linop, op* → sam), and in src/, python/, tests/ and unknown
numerics modules (and unknown crates) by context words: the nearest before the citation in the same
comment, then about 400 characters around it, then the whole file. `--list` shows how each citation
was resolved.

A bare "§N" (no "spec" before it in the same comment run) is rewritten in the same way unless it
cites a paper or book (a year, "[LN11]" (escaped `\[LN11\]` in doc comments, for rustdoc), "paper", "Section" shortly before it, e.g. "Mura 1987 §11").
Citations inside string literals (user-visible messages and headers) are reported and left alone
unless --include-strings is given.

Usage (from a repository root):
    python3 verify/rewrite_citations.py            # rewrite in place, report, exit 1 if any unmapped
    python3 verify/rewrite_citations.py --dry-run  # report what would change
    python3 verify/rewrite_citations.py --list     # also print every rewrite and how it was resolved
    python3 verify/rewrite_citations.py --check    # exit 1 if any "spec §" citation remains (CI)
    python3 verify/rewrite_citations.py --prose    # list "the spec's …" prose left for a manual pass
Also verifies that every target anchor exists as a heading in docs/ (exit 1 if not).
"""
from __future__ import annotations

import argparse
import os
import re
import signal
import sys
import unicodedata

ROOTS = ("crates", "src", "python/src", "tests")

MDR_PAGE = "docs/theory-mdr.md"
SAM_PAGE = "docs/theory-sam.md"

# spec section -> anchor of the page. Keys are section numbers as written after "§".
MDR = {
    "0": "conventions",
    "0.1": "squared-grid",
    "0.2": "finite-differences",
    "0.3": "power-sums",
    "1": "profile-transform",
    "2": "displacement-transform",
    "3": "stress-transform",
    "4": "graded-media",
    "4.1": "graded-profile-transform",
    "4.2": "graded-constant-cn",
    "4.3": "graded-displacements",
    "4.4": "graded-pressure",
    "4.5": "graded-closed-forms",
    "5": "fretting-wear",
    "6": "cost-of-the-two-backends",
    "7": "pitfalls",
    "8": "sources",
    "conventions": "conventions",
}
MDR_PITFALLS = {
    "P1": "p1-singular-kernels",
    "P2": "p2-empty-sums-and-end-weights",
    "P3": "p3-one-sided-differences-at-the-edge",
    "P4": "p4-the-origin",
    "P5": "p5-conical-profiles",
    "P6": "p6-the-apex-at-zero",
    "P7": "p7-fft-details",
    "P8": "p8-domain-size",
    "P9": "p9-contact-radius-of-a-worn-profile",
    "P10": "p10-explicit-wear-step",
    "P11": "p11-applicability-of-eqs-13-and-26",
    "P12": "p12-special-functions",
    "P13": "p13-mean-relative-errors",
}
SAM = {
    "0": "conventions",
    "1": "influence-coefficients",
    "1.1": "point-force-solutions",
    "1.2": "corner-primitives",
    "1.3": "coefficients-of-one-half-space",
    "1.4": "two-bodies",
    "2": "dc-fft",
    "3": "normal-contact",
    "3.2": "spectral-preconditioner",  # cited by numerics/circulant.rs; sam.md has no §3.2
    "4": "tangential-contact",
    "4.1": "incremental-friction-law",
    "4.2": "convex-quadratic-program",
    "4.3": "stick-slip-solver-and-force-control",
    "4.4": "loading-history",
    "4.5": "normal-tangential-alternation",
    "5": "equivalent-inclusion-method",
    "5.1": "equivalency-equation",
    "5.2": "cuboid-in-infinite-space",
    "5.3": "mirror-image-and-correction-pressure",
    "5.4": "love-rectangle-stresses",
    "5.5": "layered-operators",
    "5.6": "solving-the-eim-equations",
    "5.7": "fourier-alternative",
    "6": "eigen-displacements-and-nested-loops",
    "6.1": "eigen-displacements",
    "6.2": "nested-loops",
    "7": "validation-cases",
    "7.1": "hertz-reference",
    "7.2": "cattaneo-mindlin-reference",
    "7.3": "mindlin-deresiewicz-reference",
    "7.4": "coupled-loop-reference",
    "7.5": "kernel-reference-values",
    "7.6": "inhomogeneity-references",
    "8": "pitfalls",
    "8.1": "sign-conventions",
    "8.2": "singular-self-influence",
    "8.3": "grid-alignment",
    "8.4": "cancellation",
    "8.5": "domain-size-and-truncation",
    "8.5b": "domain-size-and-truncation",
    "8.6": "dc-fft-layout",
    "8.7": "eim-convergence",
    "8.8": "outer-loop-tolerances",
    "8.9": "tangential-solver-cycling",
    "8.10": "coupling-in-validations",
    "8.11": "history-variables",
    "8.12": "units-and-scaling",
    "conventions": "conventions",
}
DOCS = {"mdr": (MDR_PAGE, MDR), "sam": (SAM_PAGE, SAM)}

NUMERICS_MDR = ("conv1d", "power_sum", "grid", "diff", "quad", "special")
NUMERICS_SAM = ("fft", "conv2d", "layered", "circulant", "krylov", "anderson", "linop", "op")

MDR_WORDS = re.compile(
    r"\bMDR\b|fretting[-_ ]wear|fretting_wear|axisym|graded|\bc_N\b|Eq\. ?(?:[1-9]|[12]\d|3[01])\b"
    r"|χ|\bchi\b|τ|\btau\b|wear|Winkler|profile|\bk ?=|Willert|\bmdr\b",
    re.IGNORECASE,
)
SAM_WORDS = re.compile(
    r"\bsam\b|contact3d|fretting[-_ ]loop|fretting[-_ ]map|\bEIM\b|inhomogene|inclusion|p_c\b"
    r"|Cattaneo|Mindlin|Deresiewicz|\\?\[LN11\\?\]|Leroux|Nélias|Polonsky|DC-FFT|σ₃₃|μW|μP|\bgrid \d+|\b\d{2,4}²"
    r"|eigen|Eshelby|Love\b|composite|fibre",
    re.IGNORECASE,
)

SECTION = r"(?:\d+(?:\.\d+)*[a-z]?)"  # 4, 4.3, 8.5b
PITFALL = r"P\d+"
# One citation item after §: a section, an optional range, an optional pitfall list (§7 P3, P5).
ITEM = re.compile(
    rf"§\s?(?P<sec>{SECTION})(?!\d)"
    rf"(?:(?P<rng>\s?[–-]\s?§?(?P<sec2>{SECTION}))(?![\d.]\d))?"
    rf"(?P<pits>(?:(?:\s*\n\s*(?://[/!]?\s*)?|\s+)(?:{PITFALL})(?:(?:\s*(?:,|/|and)\s*){PITFALL})*))?"
)
# "spec" + optional qualifier immediately before the first §.
SPEC_HEAD = re.compile(
    r"(?P<spec>\b[Ss]pec)(?P<qual>\s+`?(?:shared/spec/)?(?P<doc>mdr|sam)\.md`?)?\s+(?=§|conventions\b)"
)
PAPER_BEFORE = re.compile(
    r"(?:\b(?:19|20)\d\d\b[^§;]{0,12}$)|(?:\\?\[LN11\\?\][^§]{0,20}$)|(?:\bpaper[^§]{0,8}$)"
    r"|(?:Section[^§]{0,4}$)|(?:\bJ\.[^§]{0,40}$)"
)
POSSESSIVE_NOUNS = (
    "graded quartic pressure", "reference run", "edge rule", "table", "rule", "iteration",
    "estimate", "loop", "values",
)
SPECIAL_PHRASES = [
    # crates/mdr/src/lib.rs: a sentence about the spec itself.
    (re.compile(r"spec `shared/spec/mdr\.md` \(equation numbers below are the paper's; § are the spec's\)"),
     "docs/theory-mdr.md (equation numbers below are the paper's)"),
]


def slug(heading: str) -> str:
    """GitHub's heading anchor: lower case, punctuation dropped, spaces to hyphens."""
    s = heading.strip().lower()
    out = []
    for ch in s:
        cat = unicodedata.category(ch)
        if ch in "-_" or ch == " ":
            out.append("-" if ch == " " else ch)
        elif cat[0] in ("L", "N", "M"):
            out.append(ch)
    return "".join(out)


def doc_anchors(root: str) -> dict[str, set[str]]:
    anchors: dict[str, set[str]] = {}
    docs = os.path.join(root, "docs")
    if not os.path.isdir(docs):
        return anchors
    for name in os.listdir(docs):
        if not name.endswith(".md"):
            continue
        seen: dict[str, int] = {}
        found = set()
        in_code = False
        with open(os.path.join(docs, name), encoding="utf-8") as fh:
            for line in fh:
                if line.lstrip().startswith("```"):
                    in_code = not in_code
                m = None if in_code else re.match(r"#{1,6}\s+(.*?)\s*#*\s*$", line)
                if m:
                    s = slug(m.group(1))
                    n = seen.get(s, 0)
                    seen[s] = n + 1
                    found.add(s if n == 0 else f"{s}-{n}")
        anchors[f"docs/{name}"] = found
    return anchors


def default_doc(path: str) -> str | None:
    parts = path.replace(os.sep, "/").split("/")
    if parts[0] == "crates" and len(parts) > 1:
        crate = parts[1]
        if crate in ("mdr", "fretting"):
            return "mdr"
        if crate == "sam":
            return "sam"
        if crate == "numerics":
            # The module's own name first, then the folders it sits in (numerics/src/fft/plan.rs).
            names = [os.path.splitext(parts[-1])[0]] + parts[-2:2:-1]
            for name in names:
                if name in ("lib", "mod", "error", "memory", "src", "tests", "benches"):
                    continue
                if name.startswith(NUMERICS_MDR):
                    return "mdr"
                if name.startswith(NUMERICS_SAM):
                    return "sam"
    return None


def context_doc(text: str) -> str | None:
    m = len(MDR_WORDS.findall(text))
    s = len(SAM_WORDS.findall(text))
    if m > s:
        return "mdr"
    if s > m:
        return "sam"
    return None


def only_in(sec: str, pits: bool) -> str | None:
    if pits:
        return "mdr"
    in_m = sec in MDR and sec != "conventions"
    in_s = sec in SAM and sec != "conventions"
    if in_m and not in_s:
        return "mdr"
    if in_s and not in_m:
        return "sam"
    return None


class Result:
    def __init__(self) -> None:
        self.rewritten = 0
        self.files = 0
        self.unmapped: list[str] = []
        self.strings: list[str] = []
        self.targets: set[tuple[str, str]] = set()
        self.log: list[str] = []


def comment_spans(src: str) -> list[tuple[int, int, str]]:
    """(start, end, kind) of every // comment and string literal, kind 'c' or 's'."""
    spans = []
    i, n = 0, len(src)
    while i < n:
        c = src[i]
        if c == "/" and src.startswith("//", i):
            j = src.find("\n", i)
            j = n if j < 0 else j
            spans.append((i, j, "c"))
            i = j
        elif c == "/" and src.startswith("/*", i):
            j = src.find("*/", i + 2)
            j = n if j < 0 else j + 2
            spans.append((i, j, "c"))
            i = j
        elif c == "r" and re.match(r'r#*"', src[i:i + 8]) and (i == 0 or not (src[i - 1].isalnum() or src[i - 1] == "_")):
            hashes = len(re.match(r"r(#*)", src[i:]).group(1))
            end = '"' + "#" * hashes
            j = src.find(end, i + 2 + hashes)
            j = n if j < 0 else j + len(end)
            spans.append((i, j, "s"))
            i = j
        elif c == '"':
            j = i + 1
            while j < n and src[j] != '"':
                j += 2 if src[j] == "\\" else 1
            spans.append((i, j + 1, "s"))
            i = j + 1
        elif c == "'" and re.match(r"'(?:[^'\\]|\\.[^']*)'", src[i:i + 12]):
            j = src.find("'", i + 1 + (1 if src[i + 1] == "\\" else 0))
            i = j + 1
        else:
            i += 1
    return spans


def clause_doc(before: str, after: str) -> str | None:
    """The document of the context word nearest before the citation (same comment, since the
    previous citation); failing that, the nearest one after it."""
    best = None
    for doc, rx in (("mdr", MDR_WORDS), ("sam", SAM_WORDS)):
        ms = list(rx.finditer(before))
        if ms and (best is None or ms[-1].end() > best[1]):
            best = (doc, ms[-1].end())
    if best:
        return best[0]
    best = None
    for doc, rx in (("mdr", MDR_WORDS), ("sam", SAM_WORDS)):
        m = rx.search(after)
        if m and (best is None or m.start() < best[1]):
            best = (doc, m.start())
    return best[0] if best else None


def resolve(sec, pits, qual_doc, path_doc, ctx_near, ctx_file, ctx_clause=None):
    """(document, how it was decided)."""
    if qual_doc:
        return qual_doc, "qualifier"
    only = only_in(sec, pits)
    if only:
        return only, "section"
    if path_doc:
        return path_doc, "crate"
    if ctx_clause:
        return ctx_clause, "clause"
    if ctx_near:
        return ctx_near, "context"
    if ctx_file:
        return ctx_file, "file"
    return None, "none"


def link(doc: str, sec: str, pits: list[str]) -> list[str] | None:
    page, table = DOCS[doc]
    if pits:
        out = []
        for p in pits:
            a = MDR_PITFALLS.get(p)
            if a is None:
                return None
            out.append(a)
        return [f"{page}#{out[0]}"] + [f"#{a}" for a in out[1:]]
    a = table.get(sec)
    if a is None:
        return None
    return [f"{page}#{a}"]


SPLIT_PITFALL = re.compile(
    r"(§\s?7)[ \t]*(\n[ \t]*//[/!]?[ \t]*)(P\d+(?:(?:\s*(?:,|/|and)\s*)P\d+)*\)?[:;,.]?)[ \t]*"
)


SPLIT_SPEC = re.compile(r"([ \t(]?)\b([Ss]pec(?: `(?:mdr|sam)\.md`)?)[ \t]*(\n[ \t]*//[/!]?[ \t]*)§")


def rewrite_file(path: str, root: str, res: Result, include_strings: bool, dry: bool) -> None:
    full = os.path.join(root, path)
    with open(full, encoding="utf-8", newline="") as fh:
        src = fh.read()
    if "§" not in src and not re.search(r"\b[Ss]pec `(?:mdr|sam)\.md`|\b[Ss]pec conventions", src):
        return
    path_doc = default_doc(path)
    ctx_file = context_doc(src)
    # "spec §7\n    /// P4, P5)": pull the pitfall list up to the line of its "§7".
    src = SPLIT_PITFALL.sub(lambda m: f"{m.group(1)} {m.group(3)}{m.group(2)}", src)
    # "… of spec\n    //! §7.6 …": the word "spec" ends one comment line and its § starts the
    # next; move the word down so that the citation is seen whole.
    src = SPLIT_SPEC.sub(
        lambda m: f"{m.group(1).strip()}{m.group(3)}{m.group(2)} §", src
    )
    spans = comment_spans(src)
    # Join consecutive // comment lines into runs so that "spec §7\n/// P5" and "spec §1, ...\n§4.2"
    # are seen together.
    out = []
    last = 0
    changed = 0
    for start, end, kind in spans:
        seg = src[start:end]
        if "§" not in seg and "spec" not in seg.lower():
            continue
        if kind == "s" and not include_strings:
            if re.search(r"[Ss]pec[^\"]{0,12}§", seg):
                line = src.count("\n", 0, start) + 1
                res.strings.append(f"{path}:{line}: {seg.strip()[:90]}")
            continue
        line0 = src.count("\n", 0, start) + 1
        lo = src.rfind("\n", 0, max(0, start - 400))
        near = src[max(0, lo):min(len(src), end + 400)]
        ctx_near = context_doc(near)
        new, n = rewrite_segment(seg, src, start, path, line0, path_doc, ctx_near, ctx_file, res)
        if n:
            out.append(src[last:start])
            out.append(new)
            last = end
            changed += n
    if changed:
        out.append(src[last:])
        new_src = "".join(out)
        res.rewritten += changed
        res.files += 1
        if not dry:
            with open(full, "w", encoding="utf-8", newline="") as fh:
                fh.write(new_src)


def rewrite_segment(seg, src, start, path, line0, path_doc, ctx_near, ctx_file, res):
    n_changed = 0
    for rx, rep in SPECIAL_PHRASES:
        seg, k = rx.subn(rep, seg)
        n_changed += k
    pieces = []
    pos = 0
    # "spec `sam.md`" with no § right after: the whole document.
    spec_active_doc = None
    spec_seen = False
    i = 0
    while True:
        m_spec = SPEC_HEAD.search(seg, pos)
        m_item = ITEM.search(seg, pos)
        m_whole = re.search(r"\b[Ss]pec `(?P<doc>mdr|sam)\.md`(?!\s*§)", seg[pos:])
        cands = [m for m in (m_spec, m_item) if m]
        whole_at = pos + m_whole.start() if m_whole else None
        if not cands and whole_at is None:
            break
        first = min([m.start() for m in cands] + ([whole_at] if whole_at is not None else []))
        if whole_at is not None and first == whole_at and (not m_spec or m_spec.start() != whole_at):
            doc = m_whole.group("doc")
            pieces.append(seg[pos:whole_at])
            pieces.append(DOCS[doc][0])
            pos = pos + m_whole.end()
            n_changed += 1
            continue
        if m_spec and m_spec.start() == first:
            qual = m_spec.group("doc")
            after = m_spec.end()
            if seg.startswith("conventions", after):
                doc = qual or path_doc or ctx_near or ctx_file
                line = line0 + seg.count("\n", 0, after)
                if doc is None:
                    res.unmapped.append(f"{path}:{line}: spec conventions (mdr or sam?)")
                    pieces.append(seg[pos:after + len("conventions")])
                    pos = after + len("conventions")
                    continue
                pieces.append(seg[pos:m_spec.start()])
                target = f"{DOCS[doc][0]}#conventions"
                res.targets.add((DOCS[doc][0], "conventions"))
                pieces.append(target)
                pos = after + len("conventions")
                n_changed += 1
                spec_seen = True
                spec_active_doc = qual
                continue
            item = ITEM.match(seg, after)
            if item is None:
                pieces.append(seg[pos:after])
                pos = after
                continue
            rep, ok = render(item, seg, qual, path, line0, path_doc, ctx_near, ctx_file, res,
                             spec_start=m_spec.start(), prev_end=pos)
            pieces.append(seg[pos:m_spec.start()])
            if ok:
                prefix, rep = possessive(seg, item.end(), rep)
                if prefix and m_spec.group("spec").startswith("S"):
                    prefix = prefix[0].upper() + prefix[1:]
                pieces.append(prefix + rep)
                pos = item.end() + (len(POSS_M.group(0)) if prefix else 0)
                n_changed += 1
            else:
                pieces.append(seg[m_spec.start():item.end()])
                pos = item.end()
            spec_seen = True
            spec_active_doc = qual
            continue
        # A bare § item.
        item = m_item
        before = seg[max(0, item.start() - 60):item.start()]
        line = line0 + seg.count("\n", 0, item.start())
        if PAPER_BEFORE.search(before) and not re.search(r"[Ss]pec", before):
            pieces.append(seg[pos:item.end()])
            pos = item.end()
            continue
        rep, ok = render(item, seg, spec_active_doc if spec_seen else None, path, line0, path_doc,
                         ctx_near, ctx_file, res, spec_start=None, prev_end=pos)
        pieces.append(seg[pos:item.start()])
        if ok:
            prefix, rep = possessive(seg, item.end(), rep)
            pieces.append(prefix + rep)
            pos = item.end() + (len(POSS_M.group(0)) if prefix else 0)
            n_changed += 1
        else:
            pieces.append(seg[item.start():item.end()])
            pos = item.end()
    pieces.append(seg[pos:])
    return "".join(pieces), n_changed


POSS_M = None


def possessive(seg, end, rep):
    """'spec §5's edge rule' -> 'the edge rule of <link>'."""
    global POSS_M
    POSS_M = None
    m = re.match(r"'s (" + "|".join(re.escape(w) for w in POSSESSIVE_NOUNS) + r")\b", seg[end:])
    if not m:
        if seg.startswith("'s", end):
            POSS_M = re.match(r"'s", seg[end:])
            return "the one of ", rep  # rare; reads "the one of docs/…"
        return "", rep
    POSS_M = m
    return f"the {m.group(1)} of ", rep


def render(item, seg, qual, path, line0, path_doc, ctx_near, ctx_file, res, spec_start, prev_end=0):
    sec = item.group("sec")
    sec2 = item.group("sec2")
    pits = re.findall(PITFALL, item.group("pits") or "")
    line = line0 + seg.count("\n", 0, item.start())
    after = seg[item.end():item.end() + 60].split("§")[0]
    ctx_clause = clause_doc(seg[prev_end:item.start()], after)
    doc, how = resolve(sec, bool(pits), qual, path_doc, ctx_near, ctx_file, ctx_clause)
    text = seg[item.start():item.end()].replace("\n", " ")
    if doc is None:
        res.unmapped.append(f"{path}:{line}: {text} (mdr or sam? no crate, qualifier or context)")
        return None, False
    links = link(doc, sec, pits)
    if links is None:
        res.unmapped.append(f"{path}:{line}: {text} (no {doc}.md section {sec} {' '.join(pits)})")
        return None, False
    if sec2:
        l2 = link(doc, sec2, [])
        if l2 is None:
            res.unmapped.append(f"{path}:{line}: {text} (no {doc}.md section {sec2})")
            return None, False
        links = links + [l2[0].split("#", 1)[1]]
        rep = f"{links[0]} to #{links[1]}"
    else:
        rep = ", ".join(links)
    for l in links:
        if l.startswith("docs/"):
            page, a = l.split("#", 1)
            res.targets.add((page, a))
        else:
            res.targets.add((DOCS[doc][0], l.lstrip("#")))
    res.log.append(f"{path}:{line}: [{how}] {seg[item.start():item.end()].strip()} -> {rep}")
    # Keep a newline that separated "§7" from "P5" out of the replacement: pitfalls on the next line
    # are consumed; the comment prefix of that line must survive.
    raw = item.group(0)
    nl = re.search(r"\n\s*//[/!]?\s*", raw)
    if nl:
        rep = rep.split(", ")[0] + nl.group(0) + ", ".join(rep.split(", ")[1:])
        rep = rep.rstrip()
        if rep.endswith("//") or rep.endswith("///") or rep.endswith("//!"):
            rep += " "
    return rep, True


def walk(root: str):
    for base in ROOTS:
        top = os.path.join(root, base)
        if not os.path.isdir(top):
            continue
        for d, dirs, files in os.walk(top):
            dirs[:] = [x for x in dirs if x not in ("target", ".git", "node_modules")]
            for f in sorted(files):
                if f.endswith(".rs"):
                    yield os.path.relpath(os.path.join(d, f), root)


REMAINING = re.compile(r"\b[Ss]pec\b[^\n]{0,24}§|\b[Ss]pec `(?:mdr|sam)\.md`|shared/spec/")


def check(root: str) -> int:
    """Exit status 1 if any citation of the external specs remains: a line that names "spec" and
    "§" (or `mdr.md`/`sam.md`, shared/spec/), or any citation the rewrite would still change
    (bare "§N" that is not a paper's section), comments and string literals alike."""
    res = Result()
    for path in walk(root):
        rewrite_file(path, root, res, include_strings=True, dry=True)
    for entry in res.log:
        print(f"would rewrite {entry}")
    for u in res.unmapped:
        print(f"UNMAPPED {u}")
    bad = []
    for path in walk(root):
        with open(os.path.join(root, path), encoding="utf-8") as fh:
            for no, line in enumerate(fh, 1):
                if REMAINING.search(line):
                    bad.append(f"{path}:{no}: {line.strip()[:110]}")
    for b in bad:
        print(b)
    print(f"{len(bad)} line(s) still cite the external specs; {len(res.log)} citation(s) would be "
          f"rewritten, {len(res.unmapped)} unmapped")
    return 1 if (bad or res.log or res.unmapped) else 0


PROSE = re.compile(r"\b[Ss]pec(?:'s)?\b(?!::|\.rs|_)")


def prose(root: str) -> int:
    """List comments that still mention "the spec" without a § (reference numbers quoted from it,
    "the spec's …"): not citations this script can map, for a manual pass. Report only."""
    n = 0
    for path in walk(root):
        with open(os.path.join(root, path), encoding="utf-8") as fh:
            src = fh.read()
        for start, end, kind in comment_spans(src):
            if kind != "c":
                continue
            seg = src[start:end]
            if re.search(r"parser|IFFT|`spec`|\(spec\)|kind:key|spec's `E`", seg):
                continue  # the CLI's `kind:key=value` specs and spectra, not the math specs
            for m in PROSE.finditer(seg):
                line = src.count("\n", 0, start + m.start()) + 1
                print(f"{path}:{line}: {seg.strip()[:110]}")
                n += 1
                break
    print(f"{n} comment(s) mention the spec without a § (report only)")
    return 0


def main() -> int:
    if hasattr(signal, "SIGPIPE"):
        signal.signal(signal.SIGPIPE, signal.SIG_DFL)
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--root", default=".")
    ap.add_argument("--check", action="store_true", help="exit 1 if any 'spec §' citation remains")
    ap.add_argument("--dry-run", action="store_true")
    ap.add_argument("--list", action="store_true",
                    help="print every rewrite with how mdr/sam was decided (qualifier, section, crate, context, file)")
    ap.add_argument("--prose", action="store_true",
                    help="list comments that mention the spec without a § (report only)")
    ap.add_argument("--include-strings", action="store_true",
                    help="also rewrite citations inside string literals (changes program output)")
    args = ap.parse_args()
    root = args.root
    if args.check:
        return check(root)
    if args.prose:
        return prose(root)
    res = Result()
    for path in walk(root):
        rewrite_file(path, root, res, args.include_strings, args.dry_run)
    anchors = doc_anchors(root)
    missing = sorted(f"{p}#{a}" for p, a in res.targets if a not in anchors.get(p, set()))
    verb = "would rewrite" if args.dry_run else "rewrote"
    if args.list:
        for entry in res.log:
            print(entry)
    print(f"{verb} {res.rewritten} citation(s) in {res.files} file(s)")
    for u in res.unmapped:
        print(f"UNMAPPED {u}")
    for s in res.strings:
        print(f"IN STRING (left alone; --include-strings rewrites) {s}")
    for m in missing:
        print(f"MISSING ANCHOR {m}")
    print(f"{len(res.unmapped)} unmapped, {len(res.strings)} in string literals, "
          f"{len(missing)} missing anchor(s)")
    return 1 if (res.unmapped or res.strings or missing) else 0


if __name__ == "__main__":
    sys.exit(main())
