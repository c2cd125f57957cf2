#!/usr/bin/env python3
"""Runs the examples of the documentation, so that a renamed option breaks the build, not the reader.

    examples.py --build BUILD [--source ROOT] [--only FILE] [--exclude FILE]... [--list]
    examples.py --links [--source ROOT]

Pages: README.md, docs/*.md and the schema pages mapstore/SCHEMA.md and mapstore/TRAJECTORY.md
(docs/history/ holds dated rounds as measured on their day: links checked, examples not).

Every fenced block of a page is one of:
  - ```sh (bash, shell) and ```python blocks: run, in order, in one scratch folder per page that
    looks like the source root (meshes/, reaching/, tests/, tools/, ... linked; build/bin and
    build/python the build's), with the build's bin/ on PATH and python/ on PYTHONPATH; a block
    fails the test when it exits non-zero;
  - ```json blocks: parsed;
  - ```cpp blocks: compiled by the build, not here (tools/docs/snippets.py, the ctest docs.cpp;
    its mark `body #include <...>` compiles statements inside a function);
  - any other block (```text, no language): not code that runs here; each of its lines
    that calls `taskmap` or `taskmap-mpi` is checked as a marked block's (below).
A comment on the line before a block marks it instead:
  <!-- docs-test: options REASON -->  not run; every `taskmap ...` line's subcommand and options
                                      are checked against that subcommand's `--help`
  <!-- docs-test: skip REASON -->     not run, not checked (the reason is printed)
  <!-- docs-test: setup COMMANDS -->  run COMMANDS (sh) in the page's folder before the block
Pages this change may not edit carry their marks in MARKS below (by page and first line).
Inline code spans that call `taskmap CMD --option` are checked like marked blocks, and spans
that name `taskmap.NAME` are checked to exist in the Python package. A block's
`build/tests/bench/PROGRAM` paths (run or not) must name programs of the build tree when it has
its benchmarks.

--links checks every relative link of README.md, docs/ (history included) and mapstore/*.md:
the file exists, and a #anchor names a heading of the target page (GitHub's slugs).

Exit status 0 when everything passes, 1 otherwise; a summary line counts the blocks run,
checked and skipped."""
import argparse
import json
import os
import re
import shutil
import subprocess
import sys
import time

# Marks of pages this change does not edit (docs/VALIDATION.md is being filled by others).
MARKS = {
    ("docs/VALIDATION.md", "taskmap validate MAP.h5 [--robust]"):
        ("options", "a synopsis: MAP.h5 stands for any map"),
    ("mapstore/SCHEMA.md", "import h5py"):
        ("setup", "taskmap build --object basket --hand barrett --valid 5 --seed 1 "
                  "--hold-test off -q -o basket_barrett.h5"),
}
PAGES_GLOBS = ["README.md", "docs/*.md", "mapstore/SCHEMA.md", "mapstore/TRAJECTORY.md"]
RUN_LANGS = {"sh": "sh", "bash": "sh", "shell": "sh", "python": "python", "py": "python"}
MARK_RE = re.compile(r"^<!--\s*docs-test:\s*(\w+)\s*(.*?)\s*-->\s*$")
FENCE_RE = re.compile(r"^(\s*)(```+|~~~+)\s*([\w+-]*)")
BLOCK_TIMEOUT = 900


class Block:
    def __init__(self, page, line, lang, text, mark):
        self.page, self.line, self.lang, self.text, self.mark = page, line, lang, text, mark

    def where(self):
        return f"{self.page}:{self.line}"


def pages(root):
    import glob
    out = []
    for g in PAGES_GLOBS:
        out += sorted(os.path.relpath(p, root) for p in glob.glob(os.path.join(root, g)))
    return out


def parse(root, page):
    """The fenced blocks of a page, with their marks; and the text outside them."""
    lines = open(os.path.join(root, page), encoding="utf-8").read().split("\n")
    blocks, prose, i = [], [], 0
    while i < len(lines):
        m = FENCE_RE.match(lines[i])
        if not m:
            prose.append((i + 1, lines[i]))
            i += 1
            continue
        indent, fence, lang = m.group(1), m.group(2), m.group(3).lower()
        start, body = i + 1, []
        i += 1
        while i < len(lines) and not lines[i].strip().startswith(fence):
            body.append(lines[i][len(indent):] if lines[i].startswith(indent) else lines[i])
            i += 1
        i += 1
        text = "\n".join(body) + "\n"
        mark = None
        k = start - 2
        while k >= 0 and not lines[k].strip():
            k -= 1
        if k >= 0:
            mm = MARK_RE.match(lines[k].strip())
            if mm:
                mark = (mm.group(1), mm.group(2))
        first = next((b.strip() for b in body if b.strip()), "")
        for (p, prefix), value in MARKS.items():
            if p == page and first.startswith(prefix):
                mark = value
        blocks.append(Block(page, start, lang, text, mark))
    return blocks, prose


class Help:
    """`taskmap --help` and each subcommand's, read once."""

    def __init__(self, bindir):
        self.bindir, self.cache = bindir, {}

    def text(self, tool, sub):
        key = (tool, sub)
        if key not in self.cache:
            exe = os.path.join(self.bindir, tool)
            if not os.path.exists(exe):
                self.cache[key] = None
            else:
                args = [exe] + ([sub] if sub else []) + ["--help"]
                r = subprocess.run(args, capture_output=True, text=True, timeout=60)
                self.cache[key] = r.stdout if r.returncode == 0 else None
        return self.cache[key]

    def commands(self, tool):
        text = self.text(tool, None) or ""
        part = text.split("Subcommands:")[1] if "Subcommands:" in text else ""
        return set(re.findall(r"^  ([a-z][a-z-]*)\s", part, re.M))


def command_lines(text):
    """Logical lines (continuations joined) that call taskmap or taskmap-mpi."""
    joined = re.sub(r"\\\n\s*", " ", text)
    out = []
    for line in joined.split("\n"):
        line = line.split(" #")[0].strip()
        for seg in re.split(r"\s*(?:&&|\|\||;|\|)\s*", line):
            if re.search(r"(^|[\s/])taskmap(-mpi)?(\s|$)", seg):
                out.append(seg)
    return out


def check_command(cmd, helps):
    """Errors of one `taskmap ...` line: an unknown subcommand or option."""
    tokens = cmd.replace("[", " ").replace("]", " ").split()
    idx = next((i for i, t in enumerate(tokens)
                if os.path.basename(t) in ("taskmap", "taskmap-mpi")), None)
    if idx is None:
        return []
    tool = os.path.basename(tokens[idx])
    rest = tokens[idx + 1:]
    if not rest or rest[0].startswith("-"):
        return []  # taskmap --help / --version
    sub = rest[0]
    if helps.text(tool, None) is None:
        return [f"{tool} is not built"]
    if sub in ("...", "<command>", "COMMAND", "CMD"):
        return []
    if sub not in helps.commands(tool):
        return [f"`{tool} {sub}`: no such command"]
    help_text = helps.text(tool, sub) or ""
    errors = []
    for t in rest[1:]:
        for opt in re.findall(r"(?:^|\|)(--?[A-Za-z][\w-]*)", t):
            if opt in ("--", "-"):
                continue
            if not re.search(r"(?<![\w-])" + re.escape(opt) + r"(?![\w-])", help_text):
                errors.append(f"`{tool} {sub}` has no option {opt}")
    return errors


def check_bench_paths(text, build):
    """Errors of a block's `build/tests/bench/...` programs: each must exist in the build tree
    (checked when the build has its benchmarks), so a renamed benchmark breaks the page."""
    bench = os.path.join(build, "tests", "bench")
    built = [f for d, _, fs in os.walk(bench) for f in fs
             if os.access(os.path.join(d, f), os.X_OK) and "CMakeFiles" not in d]
    if not built:
        return []
    return [f"{m}: no such program in the build tree"
            for m in sorted(set(re.findall(r"(?<![\w/])build/(tests/bench/[\w./-]*\w)", text)))
            if not os.path.exists(os.path.join(build, m))]


def inline_checks(prose, helps):
    """Inline `taskmap CMD ...` spans and `taskmap.NAME` spans of a page's prose."""
    errors, commands, names = [], 0, set()
    text = "\n".join(t for _, t in prose)
    for span in re.findall(r"`([^`\n]+)`", text):
        s = span.strip()
        if re.match(r"^(build/bin/)?taskmap(-mpi)? [a-z]", s):
            commands += 1
            errors += [f"`{s}`: {e}" for e in check_command(s, helps)]
        for name in re.findall(r"(?<![\w.])taskmap\.([A-Za-z]\w*)", s):
            names.add(name)
    return errors, commands, names


def check_python_names(names, build):
    if not names:
        return []
    env = dict(os.environ, PYTHONPATH=os.path.join(build, "python"))
    code = ("import sys, taskmap\n"
            "missing = [n for n in sys.argv[1:] if not hasattr(taskmap, n)]\n"
            "print('\\n'.join(missing))\n")
    r = subprocess.run([sys.executable, "-c", code] + sorted(names), capture_output=True,
                       text=True, env=env, timeout=120)
    if r.returncode != 0:
        return [f"import taskmap failed: {r.stderr.strip()[-400:]}"]
    return [f"taskmap.{n}: no such name in the Python package" for n in r.stdout.split()]


def scratch_for(root, build, page):
    """A folder that looks like the source root, for one page's examples."""
    d = os.path.join(build, "docs-examples", page.replace("/", "_").replace(".md", ""))
    shutil.rmtree(d, ignore_errors=True)
    os.makedirs(os.path.join(d, "build"))
    for entry in os.listdir(root):
        if entry.startswith(".") or entry.startswith("build") or entry == "venv":
            continue
        os.symlink(os.path.join(root, entry), os.path.join(d, entry))
    for sub in ("bin", "python", "share"):
        if os.path.exists(os.path.join(build, sub)):
            os.symlink(os.path.join(build, sub), os.path.join(d, "build", sub))
    return d


def run_block(block, cwd, env, setup=None):
    t0 = time.time()
    if setup:
        r = subprocess.run(["bash", "-e", "-o", "pipefail", "-c", setup], cwd=cwd, env=env,
                           capture_output=True, text=True, timeout=BLOCK_TIMEOUT)
        if r.returncode != 0:
            return False, time.time() - t0, "setup failed: " + (r.stdout + r.stderr)[-1500:]
    kind = RUN_LANGS[block.lang]
    args = (["bash", "-e", "-o", "pipefail", "-c", block.text] if kind == "sh"
            else [sys.executable, "-c", block.text])
    try:
        r = subprocess.run(args, cwd=cwd, env=env, capture_output=True, text=True,
                           timeout=BLOCK_TIMEOUT)
    except subprocess.TimeoutExpired:
        return False, time.time() - t0, f"timed out after {BLOCK_TIMEOUT} s"
    return r.returncode == 0, time.time() - t0, (r.stdout + r.stderr)[-2500:]


def examples(root, build, only, list_only, exclude=()):
    helps = Help(os.path.join(build, "bin"))
    env = dict(os.environ)
    env["PATH"] = os.path.join(build, "bin") + os.pathsep + env.get("PATH", "")
    env["PYTHONPATH"] = os.path.join(build, "python")
    env.pop("TASKMAP_DATA_DIR", None)
    env["TERM"] = "dumb"
    counts = {"run": 0, "options": 0, "skip": 0, "json": 0, "text": 0}
    failures, names, inline = [], set(), 0
    for page in pages(root):
        if (only and page != only) or page in exclude:
            continue
        blocks, prose = parse(root, page)
        errors, n, page_names = inline_checks(prose, helps)
        inline += n
        names |= page_names
        failures += [f"{page}: {e}" for e in errors]
        cwd = None
        for b in blocks:
            mode, reason = b.mark if b.mark else (None, "")
            if mode not in (None, "options", "skip", "setup") and not (
                    mode == "body" and b.lang in ("cpp", "c++", "cc", "cxx")):
                failures.append(f"{b.where()}: unknown mark '{mode}'")
                continue
            failures += [f"{b.where()}: {e}" for e in check_bench_paths(b.text, build)]
            if mode == "skip":
                if not reason:
                    failures.append(f"{b.where()}: a skipped block needs its reason")
                counts["skip"] += 1
                print(f"skip     {b.where()} ({b.lang}): {reason}")
                continue
            if b.lang in RUN_LANGS and mode in (None, "setup"):
                counts["run"] += 1
                if list_only:
                    print(f"run      {b.where()} ({b.lang})")
                    continue
                if cwd is None:
                    cwd = scratch_for(root, build, page)
                ok, seconds, out = run_block(b, cwd, env, reason if mode == "setup" else None)
                print(f"{'ok' if ok else 'FAILED':8} {b.where()} ({b.lang}) {seconds:.1f} s",
                      flush=True)
                if not ok:
                    failures.append(f"{b.where()}: the {b.lang} block failed:\n{out}")
                continue
            if b.lang == "json" and mode is None:
                counts["json"] += 1
                try:
                    json.loads(b.text)
                except ValueError as e:
                    failures.append(f"{b.where()}: not JSON: {e}")
                continue
            lines = command_lines(b.text)
            if mode == "options" and not reason:
                failures.append(f"{b.where()}: an options-only block needs its reason")
            counts["options" if mode == "options" or lines else "text"] += 1
            for cmd in lines:
                failures += [f"{b.where()}: {e}" for e in check_command(cmd, helps)]
            if mode == "options":
                print(f"options  {b.where()} ({b.lang}, {len(lines)} commands): {reason}")
    failures += check_python_names(names, build)
    print(f"\ndocs examples: {counts['run']} blocks run, {counts['options']} checked for their "
          f"commands' options, {counts['skip']} skipped with a reason, {counts['json']} JSON "
          f"parsed, {counts['text']} text; {inline} inline commands and {len(names)} Python "
          f"names checked; {len(failures)} failures")
    for f in failures:
        print("\nFAIL " + f)
    return 0 if not failures else 1


def slug(heading):
    h = re.sub(r"\[([^\]]*)\]\([^)]*\)", r"\1", heading.strip()).lower()
    h = re.sub(r"[^\w\- ]", "", h)
    return h.replace(" ", "-")


def anchors(path, cache={}):
    if path not in cache:
        seen, out, fence = {}, set(), False
        for line in open(path, encoding="utf-8"):
            if line.lstrip().startswith("```"):
                fence = not fence
            m = re.match(r"^#{1,6}\s+(.*?)\s*#*\s*$", line)
            if m and not fence:
                s = slug(m.group(1))
                n = seen.get(s, 0)
                seen[s] = n + 1
                out.add(s if n == 0 else f"{s}-{n}")
        cache[path] = out
    return cache[path]


def links(root):
    import glob
    files = ["README.md"] + sorted(glob.glob(os.path.join(root, "docs", "**", "*.md"),
                                             recursive=True))
    files += sorted(glob.glob(os.path.join(root, "mapstore", "*.md")))
    errors, n = [], 0
    for f in files:
        path = f if os.path.isabs(f) else os.path.join(root, f)
        text = re.sub(r"```.*?```", "", open(path, encoding="utf-8").read(), flags=re.S)
        for target in re.findall(r"\]\(([^)\s]+)\)", text):
            if re.match(r"^[a-z]+:", target):
                continue
            n += 1
            file_part, _, anchor = target.partition("#")
            dest = os.path.normpath(os.path.join(os.path.dirname(path), file_part)) \
                if file_part else path
            rel = os.path.relpath(path, root)
            if not os.path.exists(dest):
                errors.append(f"{rel}: link to {target}: no such file")
            elif anchor and dest.endswith(".md") and anchor not in anchors(dest):
                errors.append(f"{rel}: link to {target}: no heading with that anchor")
    print(f"docs links: {n} relative links checked in {len(files)} pages; "
          f"{len(errors)} broken")
    for e in errors:
        print("FAIL " + e)
    return 0 if not errors else 1


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--source", default=os.path.dirname(os.path.dirname(
        os.path.dirname(os.path.abspath(__file__)))))
    ap.add_argument("--build")
    ap.add_argument("--only", help="one page, e.g. README.md")
    ap.add_argument("--exclude", action="append", default=[], help="leave out a page")
    ap.add_argument("--list", action="store_true", help="list the blocks, run nothing")
    ap.add_argument("--links", action="store_true", help="check the relative links only")
    a = ap.parse_args()
    root = os.path.abspath(a.source)
    if a.links:
        return links(root)
    if not a.build:
        ap.error("--build BUILD is required")
    return examples(root, os.path.abspath(a.build), a.only, a.list, a.exclude)


if __name__ == "__main__":
    sys.exit(main())
