"""The user documentation matches the checkout and the binary: every relative link of README.md
and docs/*.md leads to a file of the repository (and, with #anchor, to a heading of it), and
README.md documents exactly the options that `dxlemu run --help` prints. Standard library only;
the binary is $DXLEMU_BIN, the repository the one this file is in."""
import os
import re
import subprocess
import unittest
import urllib.parse

ROOT = os.path.realpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))


def read(path):
    """The text of `path`; a file that cannot be read fails the test, naming it."""
    try:
        with open(path, encoding="utf-8") as f:
            return f.read()
    except (OSError, UnicodeDecodeError) as e:
        raise AssertionError(f"cannot read {os.path.relpath(path, ROOT)}: {e}") from e


def documents():
    """README.md and every docs/*.md, as absolute paths."""
    docs = os.path.join(ROOT, "docs")
    try:
        names = sorted(n for n in os.listdir(docs) if n.endswith(".md"))
    except OSError as e:
        raise AssertionError(f"cannot list {docs}: {e}") from e
    return [os.path.join(ROOT, "README.md")] + [os.path.join(docs, n) for n in names]


FENCE = re.compile(r"^ {0,3}(`{3,}|~{3,})")
ATX_HEADING = re.compile(r"^ {0,3}(#{1,6})[ \t]+(.*?)(?:[ \t]+#+)?[ \t]*$")


def scan(text):
    """By CommonMark's rules (a closing fence is the opening fence's character, at least as many,
    and nothing else on the line): the (line number, line) pairs outside fenced code blocks, and
    the line numbers where a fence meant to close a block does not (text follows it, so the block
    goes on and every later fence is off by one), or where a block is left open at the end."""
    prose, unclosed = [], []
    fence = None
    opened_at = None
    for number, line in enumerate(text.splitlines(), 1):
        marker = FENCE.match(line)
        if fence is None:
            if marker:
                fence, opened_at = marker.group(1), number
            else:
                prose.append((number, line))
        elif marker and marker.group(1)[0] == fence[0] and len(marker.group(1)) >= len(fence):
            if line.strip().strip(fence[0]):
                unclosed.append(number)
            else:
                fence = None
    if fence is not None:
        unclosed.append(opened_at)
    return prose, unclosed


def prose_lines(text):
    """(line number, line) of every line outside fenced code blocks."""
    return scan(text)[0]


def without_code_spans(line):
    """The line with `inline code` blanked out: a link in code is not a link."""
    return re.sub(r"(`+)(?:(?!\1).)+?\1", lambda m: " " * len(m.group(0)), line)


def slug(heading):
    """GitHub's anchor for a heading: the rendered text, lower case, punctuation dropped (letters,
    digits, spaces, '-' and '_' stay), each space a '-'."""
    text = re.sub(r"!?\[([^\]]*)\]\([^)]*\)", r"\1", heading)  # a link's text
    text = re.sub(r"<[^>]+>", "", text)                          # inline HTML
    text = text.replace("`", "").replace("*", "")
    text = "".join(c for c in text.lower() if c.isalnum() or c in " -_")
    return text.replace(" ", "-")


def anchors(text):
    """Every anchor of a Markdown text: its headings' slugs (a repeated slug gets -1, -2, ... as
    on GitHub) and the id/name of HTML elements."""
    seen = {}
    found = set()
    for _, line in prose_lines(text):
        heading = ATX_HEADING.match(line)
        if heading:
            base = slug(heading.group(2))
            count = seen.get(base, 0)
            seen[base] = count + 1
            found.add(base if count == 0 else f"{base}-{count}")
        found.update(re.findall(r"""<[a-zA-Z][^>]*\s(?:id|name)=["']([^"']+)["']""", line))
    return found


INLINE_LINK = re.compile(r"!?\[(?:[^\[\]]|\[[^\]]*\])*\]\(\s*<?([^)\s>]*)>?(?:\s+[\"'(][^)]*)?\)")
REFERENCE_DEFINITION = re.compile(r"^ {0,3}\[[^\]]+\]:\s*<?(\S+?)>?(?:\s.*)?$")


def links(text):
    """(line number, target) of every link and image of a Markdown text, code excluded."""
    for number, line in prose_lines(text):
        definition = REFERENCE_DEFINITION.match(line)
        if definition:
            yield number, definition.group(1)
            continue
        for match in INLINE_LINK.finditer(without_code_spans(line)):
            yield number, match.group(1)


def is_relative(target):
    """A link into the repository: no scheme (http:, mailto:, ...) and not protocol-relative."""
    return not re.match(r"^[a-zA-Z][a-zA-Z0-9+.-]*:", target) and not target.startswith("//")


def problems_of(path):
    """What is wrong with the relative links of one file, one sentence each."""
    problems = []
    here = os.path.dirname(path)
    name = os.path.relpath(path, ROOT)
    text = read(path)
    for number in scan(text)[1]:
        problems.append(f"{name}:{number}: a code block is not closed here (a closing fence must "
                        "have nothing after it on its line), so prose is shown as code")
    for number, target in links(text):
        if not target or not is_relative(target):
            continue
        file_part, _, anchor = target.partition("#")
        file_part = urllib.parse.unquote(file_part)
        where = f"{name}:{number}: ({target})"
        destination = os.path.realpath(os.path.join(here, file_part)) if file_part else path
        if os.path.commonpath([destination, ROOT]) != ROOT:
            problems.append(f"{where} leads outside the repository, to {destination}")
            continue
        if not os.path.exists(destination):
            problems.append(f"{where} names {os.path.relpath(destination, ROOT)}, "
                            "which does not exist")
            continue
        if anchor:
            if not destination.endswith(".md") or os.path.isdir(destination):
                problems.append(f"{where} has an anchor, but "
                                f"{os.path.relpath(destination, ROOT)} is not a Markdown file")
            elif urllib.parse.unquote(anchor).lower() not in anchors(read(destination)):
                problems.append(f"{where}: {os.path.relpath(destination, ROOT)} has no heading "
                                f"with the anchor #{anchor}")
    return problems


class RelativeLinksTest(unittest.TestCase):
    def test_every_relative_link_of_readme_and_docs_resolves(self):
        files = documents()
        self.assertGreater(len(files), 1, "no docs/*.md found")
        problems = [p for f in files for p in problems_of(f)]
        self.assertEqual(problems, [], "broken links and code blocks:\n" + "\n".join(problems))

    def test_the_check_finds_links_and_anchors_outside_code(self):
        text = "\n".join([
            "# Title",
            "See [a](a.md), ![b](img/b.png \"title\") and [c](c.md#part-two); `[d](d.md)` is code.",
            "[ref]: e.md#top",
            "```sh",
            "# not a heading, [f](f.md) not a link",
            "```",
            "## Part two: `--x` (y)",
            "## Part two: `--x` (y)",
            '<a id="here"></a>',
        ])
        self.assertEqual([t for _, t in links(text)],
                         ["a.md", "img/b.png", "c.md#part-two", "e.md#top"])
        self.assertEqual(anchors(text),
                         {"title", "part-two---x-y", "part-two---x-y-1", "here"})
        self.assertEqual(slug("State file (`--state FILE`)"), "state-file---state-file")
        self.assertEqual(ATX_HEADING.match("## C# and F# ##").group(2), "C# and F#")
        self.assertEqual(scan("```\ncode\n```  # no close\ntext\n")[1], [3, 1])


OPTION_AT_LINE_START = re.compile(r"^\s+(?:-[a-zA-Z],)?(--[a-z][a-z0-9-]*)")
OPTION = re.compile(r"(?<![\w-])--[a-z][a-z0-9-]*")


def help_options():
    """The long options `dxlemu run --help` lists (without --help itself)."""
    binary = os.environ.get("DXLEMU_BIN")
    if not binary:
        raise AssertionError("DXLEMU_BIN is not set: it must name the dxlemu binary to test")
    if not os.access(binary, os.X_OK):
        raise AssertionError(f"DXLEMU_BIN={binary} is not an executable file")
    result = subprocess.run([binary, "run", "--help"], capture_output=True, text=True, timeout=30)
    if result.returncode != 0:
        raise AssertionError(f"{binary} run --help exited with {result.returncode}:\n"
                             f"{result.stdout}{result.stderr}")
    options = {m.group(1) for line in result.stdout.splitlines()
               if (m := OPTION_AT_LINE_START.match(line))}
    options.discard("--help")
    if not options:
        raise AssertionError(f"{binary} run --help lists no options:\n{result.stdout}")
    return options


def readme_run_options():
    """The options README.md documents for `dxlemu run`, in its section "Running the emulator":
    those of the synopsis (the `dxlemu run` line and the lines continuing it) and those each
    bullet starts with ("- `--seed N`: ..."), as two sets."""
    text = read(os.path.join(ROOT, "README.md"))
    section = re.search(r"^## Running the emulator\n(.*?)(?=^## )", text, re.M | re.S)
    if not section:
        raise AssertionError("README.md has no section \"## Running the emulator\"")
    synopsis, bullets = set(), set()
    in_run = False
    for line in section.group(1).splitlines():
        if line.startswith("dxlemu "):
            in_run = line.startswith("dxlemu run ")
        elif not line.startswith(" "):
            in_run = False
        if in_run:
            synopsis.update(o for o in OPTION.findall(line) if o != "--help")
        bullet = re.match(r"^- `(--[a-z][a-z0-9-]*)", line)
        if bullet:
            bullets.add(bullet.group(1))
    if not synopsis or not bullets:
        raise AssertionError("README.md's \"Running the emulator\" has no `dxlemu run` synopsis "
                             "or no option bullets")
    return synopsis, bullets


class ReadmeRunOptionsTest(unittest.TestCase):
    def test_readme_documents_every_run_option_and_no_other(self):
        printed = help_options()
        synopsis, bullets = readme_run_options()
        gaps = {
            "printed by `dxlemu run --help`, missing from README.md's synopsis":
                sorted(printed - synopsis),
            "printed by `dxlemu run --help`, without a bullet in README.md":
                sorted(printed - bullets),
            "documented for `dxlemu run` in README.md, not printed by --help":
                sorted((synopsis | bullets) - printed),
        }
        gaps = {what: options for what, options in gaps.items() if options}
        self.assertEqual(gaps, {}, "\n".join(f"{what}: {', '.join(options)}"
                                             for what, options in gaps.items()))


def setup_packages():
    """The Debian packages scripts/setup.sh installs: the words of its `packages=(...)` array."""
    text = read(os.path.join(ROOT, "scripts", "setup.sh"))
    array = re.search(r"^packages=\((.*?)^\)", text, re.M | re.S)
    if not array:
        raise AssertionError("scripts/setup.sh has no packages=( ... ) array")
    return {word for line in array.group(1).splitlines()
            for word in line.split("#", 1)[0].split()}


def readme_requirements():
    """The package names README.md's "Requirements" section lists in its bullets: the
    comma-separated names after each bullet's colon, "and" and the parenthesised remarks aside."""
    text = read(os.path.join(ROOT, "README.md"))
    section = re.search(r"^## Requirements\n(.*?)(?=^## )", text, re.M | re.S)
    if not section:
        raise AssertionError("README.md has no section \"## Requirements\"")
    names = set()
    for bullet in re.findall(r"^- [^:]*:(.*?)(?=^- |^$)", section.group(1), re.M | re.S):
        bullet = re.sub(r"\([^)]*\)", "", bullet.replace("`", ""))
        for part in re.split(r",|\band\b|;", bullet):
            if part.strip(" .\n"):
                names.add(part.strip(" .\n"))
    if not names:
        raise AssertionError("README.md's Requirements list no packages")
    return names


class ReadmeRequirementsTest(unittest.TestCase):
    def test_readme_lists_exactly_what_setup_installs(self):
        installed, listed = setup_packages(), readme_requirements()
        self.assertEqual(sorted(installed - listed), [],
                         "installed by scripts/setup.sh, not in README.md's Requirements")
        self.assertEqual(sorted(listed - installed), [],
                         "in README.md's Requirements, not installed by scripts/setup.sh")


class ArchitectureNamesEverySourceFileTest(unittest.TestCase):
    """docs/architecture.md is where a newcomer finds where things live: it names every source
    file under emulator/ by its path there (`io/pty_link.*` names pty_link.hpp and .cpp), and
    names no file that is gone."""

    NAMED = re.compile(r"`((?:[a-z0-9_]+/)+[a-z0-9_]+)\.(\*|hpp|cpp)`")

    def test_every_source_file_is_named_and_every_name_is_a_file(self):
        emulator = os.path.join(ROOT, "emulator")
        sources = set()
        for folder, _, names in os.walk(emulator):
            for name in names:
                if name.endswith((".hpp", ".cpp")):
                    sources.add(os.path.relpath(os.path.join(folder, name), emulator))
        self.assertTrue(sources, f"no source files under {emulator}")
        named = set()
        for stem, ext in self.NAMED.findall(read(os.path.join(ROOT, "docs", "architecture.md"))):
            found = {f"{stem}.{e}" for e in ("hpp", "cpp") if ext in ("*", e)} & sources
            if stem.split("/")[0] in {"sim", "wire", "model", "physics", "bus", "faults",
                                      "control", "io", "scan", "app"}:
                self.assertTrue(found, f"docs/architecture.md names `{stem}.{ext}`, which is "
                                       f"not a source file under emulator/")
            named |= found
        missing = sorted(sources - named)
        self.assertEqual(missing, [], "docs/architecture.md does not name these files of "
                                      "emulator/ (write `DIR/FILE.*` where its job is told): "
                                      + ", ".join(missing))


if __name__ == "__main__":
    unittest.main()
