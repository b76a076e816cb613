#!/usr/bin/env python3
"""No function in src/ or python/core.cpp is over 80 lines (README.md, "Layout"): a longer
one holds more than one step of its work, and each step wants its own name.

A function's length is the lines of its body between its braces, the braces' own lines
left out. Comments, string literals and preprocessor lines are blanked first, so that no
brace inside them counts; a lambda or a local class counts toward the function holding it.
Usage: function_length_test.py SOURCE_DIR [--limit N]. Exit status 1 naming every function
over the limit, with its file, line and length."""

import pathlib
import re
import sys

LIMIT = 80
SUFFIXES = (".cpp", ".hpp", ".inc", ".in")
SCOPE_KEYWORDS = re.compile(r"\b(namespace|class|struct|union|enum)\b")
# What may stand between a parameter list and the body's brace.
QUALIFIERS = {"const", "override", "final", "noexcept", "mutable", "volatile", "try"}


def blank(text):
    """`text` with comments, string and character literals and preprocessor lines replaced
    by spaces (line breaks kept), so braces and parentheses are the code's alone."""
    out, i, n = [], 0, len(text)
    at_line_start = True
    while i < n:
        c = text[i]
        if at_line_start and c == "#":  # a directive, with its continuation lines
            j = i
            while j < n and (text[j] != "\n" or text[j - 1] == "\\"):
                j += 1
            out.append(re.sub(r"[^\n]", " ", text[i:j]))
            i = j
            continue
        if c == "\n":
            at_line_start = True
        elif not c.isspace():
            at_line_start = False
        if text.startswith("//", i):
            j = text.find("\n", i)
            j = n if j < 0 else j
        elif text.startswith("/*", i):
            j = text.find("*/", i + 2)
            j = n if j < 0 else j + 2
        elif (raw := re.match(r'R"([^(\s]*)\(', text[i:i + 20])) and (i == 0 or not text[i - 1].isalnum()):
            j = text.find(")" + raw.group(1) + '"', i)
            j = n if j < 0 else j + len(raw.group(1)) + 2
        elif c == '"' or (c == "'" and not (i > 0 and text[i - 1].isalnum())):  # not a digit separator
            j = i + 1
            while j < n and text[j] != c:
                j += 2 if text[j] == "\\" else 1
            j += 1
        else:
            out.append(c)
            i += 1
            continue
        out.append(re.sub(r"[^\n]", " ", text[i:j]))
        i = j
    return "".join(out)


def matching(code, open_at):
    """The index of the brace closing the one at `open_at`."""
    depth = 0
    for k in range(open_at, len(code)):
        if code[k] == "{":
            depth += 1
        elif code[k] == "}":
            depth -= 1
            if depth == 0:
                return k
    return len(code) - 1


def top_level(head):
    """`head` with everything inside parentheses and angle-free brackets dropped."""
    depth, kept = 0, []
    for c in head:
        depth += c == "("
        if depth == 0:
            kept.append(c)
        depth -= c == ")" and depth > 0
    return "".join(kept)


def functions(code):
    """(name, line of the opening brace, body lines) of every function body in `code`."""
    found, head_start, k = [], 0, 0
    while k < len(code):
        c = code[k]
        if c in ";}":
            head_start = k + 1
        elif c == "{":
            head = code[head_start:k]
            outer = top_level(head)
            if SCOPE_KEYWORDS.search(outer) or ")" not in head:
                head_start = k + 1  # a namespace or class: its members are heads of their own
            elif "=" in outer.split("(")[0] or re.search(r"[=,]\s*$|\breturn\s*$", outer):
                k = matching(code, k)  # an initializer
            elif (init := re.search(r"\)\s*:(?!:)", head)) and re.search(r"\w\s*$", head) and \
                    head.split()[-1] not in QUALIFIERS and init.start() < len(head.rstrip()) - 1:
                k = matching(code, k)  # a member's braced initializer in a constructor's list
            else:
                close = matching(code, k)
                names = re.findall(r"([~\w:]+)\s*(?:<[^()]*>)?\s*\(", head)
                first = code.count("\n", 0, k) + 1
                found.append((names[0] if names else "?", first, code.count("\n", k, close) - 1))
                k, head_start = close, close + 1
        k += 1
    return found


def main(root, limit=LIMIT):
    root = pathlib.Path(root)
    files = sorted(f for f in (root / "src").rglob("*") if f.is_file() and f.suffix in SUFFIXES)
    files.append(root / "python" / "core.cpp")
    counted, over = 0, []
    for file in files:
        for name, line, length in functions(blank(file.read_text())):
            counted += 1
            if length > limit:
                over.append(f"{file.relative_to(root)}:{line}: {name} has {length} lines (at most {limit})")
    for line in over:
        print("too long:", line)
    print(f"{counted} functions in {len(files)} files, {len(over)} over {limit} lines")
    return 1 if over or counted == 0 else 0


if __name__ == "__main__":
    arguments = sys.argv[1:]
    limit = LIMIT
    if "--limit" in arguments:
        at = arguments.index("--limit")
        limit = int(arguments[at + 1])
        del arguments[at:at + 2]
    sys.exit(main(arguments[0], limit))
