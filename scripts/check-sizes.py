#!/usr/bin/env python3
"""Checks the sizes that docs/architecture.md promises: no file in src/ over MAX_FILE lines and no function
over MAX_FUNCTION lines (from its signature's first line to its closing brace, lambdas inside it counted).

A function is found as a brace block that opens at namespace level (or in a class body) after a line that
looks like a signature: not a namespace, class, struct, enum, union or initialiser list. Comments and string
literals are blanked first so their braces do not count. Prints every offender; exits 1 if there is one.
Run: python3 scripts/check-sizes.py [ROOT] (CTest runs it as style.sizes)."""
import pathlib
import re
import sys

MAX_FILE, MAX_FUNCTION = 500, 80


def blank(text):
    """Comments, string and character literals replaced by spaces (newlines kept)."""
    out, i, n = [], 0, len(text)
    while i < n:
        c = text[i]
        if text.startswith("//", i):
            j = text.find("\n", i)
            j = n if j < 0 else j
            out.append(" " * (j - i)); i = j
        elif text.startswith("/*", i):
            j = text.find("*/", i + 2)
            j = n if j < 0 else j + 2
            out.append(re.sub(r"[^\n]", " ", text[i:j])); i = j
        elif text.startswith('R"', i) and (i == 0 or not (text[i - 1].isalnum() or text[i - 1] == "_")):
            m = re.match(r'R"([^(]*)\(', text[i:])
            end = text.find(")" + m.group(1) + '"', i) + len(m.group(1)) + 2
            out.append(re.sub(r"[^\n]", " ", text[i:end])); i = end
        elif c in "\"'":
            j = i + 1
            while j < n and text[j] != c:
                j += 2 if text[j] == "\\" else 1
            out.append(" " * (j + 1 - i)); i = j + 1
        else:
            out.append(c); i += 1
    return "".join(out)


def functions(path):
    text = blank(path.read_text())
    text = re.sub(r"(?m)^[ \t]*#.*$", lambda m: " " * len(m.group(0)), text)  # preprocessor lines
    lines = text.split("\n")
    stack = []  # (kind, start line)
    found = []
    line_of = []
    for ln, line in enumerate(lines):
        line_of.extend([ln] * (len(line) + 1))
    pos = 0
    for i, c in enumerate(text):
        if c == "{":
            ln = line_of[i]
            # the statement before the brace: back to the previous ; { or }
            j = i - 1
            while j >= 0 and text[j] not in ";{}":
                j -= 1
            head = " ".join(text[j + 1:i].split())
            enclosing_is_scope = all(k in ("namespace", "class") for k, _ in stack)
            if re.match(r"^(namespace|extern)\b", head) or head.startswith("namespace") or head == "":
                kind = "namespace" if head.startswith(("namespace", "extern")) else "block"
            elif re.match(r"^(template\s*<.*>\s*)?(class|struct|union|enum)\b", head) or re.search(r"\b(class|struct|enum)\s+\w+(\s*final)?(\s*:[^()]*)?$", head):
                kind = "class"
            elif enclosing_is_scope and "(" in head and not head.endswith("=") and not re.search(r"=\s*$", head):
                kind = "function"
            else:
                kind = "block"
            k = j + 1
            while k < i and text[k].isspace():
                k += 1
            start = line_of[k]
            stack.append((kind, start))
        elif c == "}" and stack:
            kind, start = stack.pop()
            if kind == "function":
                found.append((start + 1, line_of[i] - start + 1, lines[start].strip()[:90]))
    return found


def main():
    root = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else pathlib.Path(__file__).resolve().parent.parent)
    bad = 0
    for path in sorted((root / "src").rglob("*")):
        if path.suffix not in (".h", ".cpp"):
            continue
        n = len(path.read_text().split("\n"))
        if n > MAX_FILE:
            print(f"{path.relative_to(root)}: {n} lines (at most {MAX_FILE})"); bad += 1
        for line, length, head in functions(path):
            if length > MAX_FUNCTION:
                print(f"{path.relative_to(root)}:{line}: a function of {length} lines (at most {MAX_FUNCTION}): {head}"); bad += 1
    print(f"{bad} over the limits" if bad else f"every file in src/ under {MAX_FILE} lines, every function under {MAX_FUNCTION}")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
