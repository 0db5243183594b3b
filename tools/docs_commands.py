"""Every ``shimmy`` command line shown in the README and docs/, found and checked (or run).

Found: in fenced code blocks, every line (``\\`` continuations joined, ``&&``/``;`` chains split, ``# ...``
comments dropped) whose command is ``shimmy`` or ``.venv/bin/shimmy``; in the text, every inline code span that is
such a command (a span of only the program and a command name, ``shimmy sweep``, names the command and is not
checked).  An inline span is a *synopsis*, not a command, when it has ``[``, ``|``, ``...`` or an upper-case
placeholder word of :data:`PLACEHOLDER` (``MODEL``, ``FILE.toml``, ``KMH``): the command table describes options
that way.

Usage (from the repository root)::

    .venv/bin/python tools/docs_commands.py --list             # every command with file:line (and the synopses)
    .venv/bin/python tools/docs_commands.py --syntax           # parse each through the CLI's own parser; fast
    .venv/bin/python tools/docs_commands.py --run [--only TEXT] [--timeout S]   # execute them (slow: minutes)

``--syntax`` also checks that every ``--option`` of a synopsis is an option of its command, and runs each command
line through :func:`comparisons.cli.main.build_parser` and the pressure rules that every
command applies before its work (:func:`comparisons.cli.options.pressures_of`), nothing more: no model is
built and no file is read.  ``tests/docs/test_docs_commands.py`` runs it.

``--run`` executes each command in a scratch folder, in the order of the docs (so ``shimmy params --write
mytruck.toml`` comes before the commands that read it).  Placeholders: an ``--axle FILE.toml`` that does not exist
there is first written as the paper's axle (``shimmy params --write FILE.toml``), and the folders of relative output
paths (``docs/figures/...``) are created in the scratch folder, and a file of the repository that a command reads
(``--tyre tests/data/....tir``, ``--axle docs/examples/....toml``) is copied there, so nothing in the checkout is
overwritten.  Commands
that need an outside service (``--scheduler tcp://host:8786``, a Dask cluster) are only parsed.  A command line that
was run already (``shimmy verify --quick`` is shown seven times) is reported as the same, not run again.
"""

from __future__ import annotations

import argparse
import contextlib
import functools
import io
import os
import re
import shlex
import shutil
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
DOC_GLOBS = ("README.md", "docs/**/*.md", "mbs_shimmy/README.md", "CHANGELOG.md")
PROGRAMS = ("shimmy", ".venv/bin/shimmy")
FENCE = re.compile(r"^\s*```")
INLINE = re.compile(r"(?<!`)`([^`\n]+)`(?!`)")
# The placeholder words of the synopses; a fixed list, because axle entries (I1, Fz0) are upper case too.
PLACEHOLDER = re.compile(r"\b(MODEL|FILE|DIR|KMH|BAR|NAME|VALUE|SPEC|LO|HI|N|S|SECONDS|FROM|TO|DEG|ADDRESS|PATH|"
                         r"COMMAND|COLUMN|LIST)\b")
NEEDS_SERVICE = ("--scheduler",)


@dataclass(frozen=True)
class Command:
    where: str            # file:line
    text: str             # as shown, one line
    argv: tuple[str, ...]  # the arguments after the program name
    synopsis: bool = False


def _is_synopsis(text: str) -> bool:
    return any(s in text for s in ("[", "|", "...")) or bool(PLACEHOLDER.search(text))


def _commands_in_line(line: str) -> list[str]:
    """The ``shimmy`` segments of one shell line: ``a && .venv/bin/shimmy verify`` gives ``.venv/bin/shimmy verify``."""
    try:
        lexer = shlex.shlex(line, posix=True, punctuation_chars=";&|")
        lexer.whitespace_split = True
        lexer.commenters = "#"
        tokens = list(lexer)
    except ValueError:
        return []
    # A segment after a pipe is not a command line (a markdown table in a code block splits on '|' too).
    segments, current, starts_line = [], [], True
    for tok in tokens:
        if tok in ("&&", ";", "||", "|", "&"):
            if starts_line:
                segments.append(current)
            current, starts_line = [], tok != "|"
        else:
            current.append(tok)
    if starts_line:
        segments.append(current)
    return [shlex.join(s) for s in segments if s and s[0] in PROGRAMS]


def _argv(text: str) -> tuple[str, ...]:
    return tuple(shlex.split(text)[1:])


def find(root: Path = ROOT) -> list[Command]:
    files: set[Path] = set()
    for pattern in DOC_GLOBS:
        files.update(root.glob(pattern))
    out: list[Command] = []
    for path in sorted(files):
        rel = path.relative_to(root)
        lines = path.read_text(encoding="utf-8").splitlines()
        in_code = False
        pending, start = "", 0
        for number, line in enumerate(lines, 1):
            if FENCE.match(line):
                in_code = not in_code
                continue
            if in_code:
                if not pending:
                    start = number
                if line.rstrip().endswith("\\"):
                    pending += line.rstrip()[:-1] + " "
                    continue
                joined, pending = pending + line, ""
                for text in _commands_in_line(joined):
                    out.append(Command(f"{rel}:{start}", text, _argv(text)))
                continue
            for m in INLINE.finditer(line):
                span = m.group(1).strip()
                words = span.split()
                # `shimmy sweep` in a sentence names the command; it is not a command line to run.
                if len(words) < 3 and not any(w.startswith("-") for w in words) or words[0] not in PROGRAMS:
                    continue
                synopsis = _is_synopsis(span)
                out.append(Command(f"{rel}:{number}", span, () if synopsis else _argv(span), synopsis))
    return out


def check_syntax(cmd: Command) -> str | None:
    """None when the line parses and passes the pre-work pressure rules; else the CLI's one-line message."""
    from axles.limits import UsageError
    from comparisons.cli.main import parse_command
    from axles.parameters import ParameterError
    err = io.StringIO()
    try:
        with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
            parse_command(list(cmd.argv))
    except SystemExit as exc:
        if exc.code not in (0, None):
            return err.getvalue().strip() or f"exit {exc.code}"
    except (UsageError, ParameterError) as exc:
        return f"shimmy: error: {exc}"
    return None


@functools.lru_cache(maxsize=None)
def _subcommands() -> dict[str, argparse.ArgumentParser]:
    from comparisons.cli.main import build_parser
    parser = build_parser()
    return next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction)).choices


def check_synopsis(cmd: Command) -> str | None:
    """None when every ``--option`` a synopsis names is an option of its command (a renamed option fails here)."""
    words = cmd.text.split()
    commands = _subcommands()
    if len(words) < 2 or words[1] not in commands:
        return None if len(words) > 1 and PLACEHOLDER.fullmatch(words[1]) else f"unknown command {words[1:2]}"
    known = commands[words[1]]._option_string_actions
    named = set(re.findall(r"(?<![\w-])--[a-z][a-z0-9-]*", cmd.text))
    unknown = sorted(named - set(known))
    return f"no such option of '{words[1]}': {', '.join(unknown)}" if unknown else None


def _program() -> list[str]:
    script = ROOT / ".venv" / "bin" / "shimmy"
    return [str(script)] if script.exists() else [sys.executable, "-m", "comparisons.cli"]


def _prepare(argv: tuple[str, ...], scratch: Path) -> None:
    """Placeholders in the scratch folder: the files of the repository a command reads (an axle, a ``.tir`` file),
    the axle file a command reads that the repository does not have, the folders its outputs go to."""
    for i, tok in enumerate(argv):
        relative = not tok.startswith(("-", "/")) and "=" not in tok and "://" not in tok
        if relative and (ROOT / tok).is_file() and not (scratch / tok).exists():
            (scratch / tok).parent.mkdir(parents=True, exist_ok=True)   # docs/examples/..., tests/data/...: itself
            shutil.copyfile(ROOT / tok, scratch / tok)
        elif tok == "--axle" and i + 1 < len(argv) and not (ROOT / argv[i + 1]).is_file() \
                and not (scratch / argv[i + 1]).exists():
            (scratch / argv[i + 1]).parent.mkdir(parents=True, exist_ok=True)
            subprocess.run(_program() + ["params", "--write", argv[i + 1]], cwd=scratch, check=True,
                           stdout=subprocess.DEVNULL)
        elif relative and "/" in tok:
            (scratch / tok).parent.mkdir(parents=True, exist_ok=True)


def run(cmd: Command, scratch: Path, timeout: float) -> tuple[int | str, float, str]:
    if any(opt in cmd.argv for opt in NEEDS_SERVICE):
        problem = check_syntax(cmd)
        return ("parsed only" if problem is None else 2), 0.0, problem or "needs an outside service"
    _prepare(cmd.argv, scratch)
    t0 = time.monotonic()
    try:
        done = subprocess.run(_program() + list(cmd.argv), cwd=scratch, capture_output=True, text=True,
                              timeout=timeout, env={**os.environ, "PYTHONPATH": str(ROOT)})
    except subprocess.TimeoutExpired:
        return "timeout", time.monotonic() - t0, ""
    tail = done.stderr.strip().splitlines()[-1:] if done.returncode else []
    return done.returncode, time.monotonic() - t0, tail[0] if tail else ""


def main(argv: list[str] | None = None) -> int:
    sys.path.insert(0, str(ROOT))
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    how = ap.add_mutually_exclusive_group(required=True)
    how.add_argument("--list", action="store_true", help="print every command found, with file:line")
    how.add_argument("--syntax", action="store_true", help="parse every command with the CLI's parser (fast)")
    how.add_argument("--run", action="store_true", help="execute every command in a scratch folder (slow)")
    ap.add_argument("--only", metavar="TEXT", help="only the commands containing TEXT")
    ap.add_argument("--timeout", type=float, default=1800.0, metavar="S", help="per command in --run (default 1800)")
    args = ap.parse_args(argv)
    commands = [c for c in find() if args.only is None or args.only in c.text]
    if args.list:
        for c in commands:
            print(f"{c.where}\t{'synopsis' if c.synopsis else 'command'}\t{c.text}")
        return 0
    synopses = [c for c in commands if c.synopsis]
    commands = [c for c in commands if not c.synopsis]
    bad = 0
    if args.syntax:
        for c in synopses + commands:
            problem = check_synopsis(c) if c.synopsis else check_syntax(c)
            if problem:
                bad += 1
                print(f"{c.where}: {c.text}\n    {problem}")
        print(f"docs_commands: {len(commands)} commands and {len(synopses)} synopses checked, {bad} wrong",
              file=sys.stderr)
        return 1 if bad else 0
    with tempfile.TemporaryDirectory(prefix="shimmy-docs-") as scratch:
        first: dict[tuple[str, ...], str] = {}
        for c in commands:
            if c.argv in first:     # the same line again, after the same files: it was run already
                print(f"{'same':>11} {0.0:7.1f} s  {c.where}: {c.text}\n{'':22}as {first[c.argv]}", flush=True)
                continue
            first[c.argv] = c.where
            code, seconds, tail = run(c, Path(scratch), args.timeout)
            bad += code not in (0, "parsed only")
            print(f"{code!s:>11} {seconds:7.1f} s  {c.where}: {c.text}" + (f"\n{'':22}{tail}" if tail else ""),
                  flush=True)
    print(f"docs_commands: {len(commands) - bad} of {len(commands)} commands exit 0", file=sys.stderr)
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
