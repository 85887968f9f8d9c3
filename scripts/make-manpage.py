#!/usr/bin/env python3
"""Writes the man page symphong(1) from the program's own --help texts (the top level and each command),
so the page never disagrees with the program. Usage: make-manpage.py SYMPHONG_BINARY VERSION OUT.1
(CMake runs it at build time; `cmake --install` and the Debian package install the page)."""
import re
import subprocess
import sys


def help_text(binary, *args):
    out = subprocess.run([binary, *args, "--help"], capture_output=True, text=True, check=True).stdout
    return out.replace(binary, "symphong")


def roff(text):
    """Preformatted text, safe for troff: backslashes doubled, a leading dot or quote escaped."""
    lines = []
    for line in text.rstrip("\n").split("\n"):
        line = line.replace("\\", "\\e")
        if line.startswith((".", "'")):
            line = "\\&" + line
        lines.append(line)
    return "\n".join(lines)


def main():
    binary, version, out = sys.argv[1:4]
    top = help_text(binary)
    commands = re.findall(r"^  (\w+)\s{2,}", top.split("Subcommands:")[1], re.M)
    page = [f'.TH SYMPHONG 1 "" "symphong {version}" "User Commands"',
            ".SH NAME",
            "symphong \\- a Phong path tracer built to compare Monte Carlo estimators, symmetric sampling among them",
            ".SH SYNOPSIS",
            ".B symphong",
            "[\\fB\\-\\-help\\fR] [\\fB\\-\\-version\\fR] \\fICOMMAND\\fR [\\fIOPTIONS\\fR]",
            ".SH DESCRIPTION",
            ".nf", roff(top), ".fi",
            ".SH COMMANDS"]
    for command in commands:
        page += [f".SS symphong {command}", ".nf", roff(help_text(binary, command)), ".fi"]
    page += [".SH EXIT STATUS", "0 on success, 2 for bad input (a message names the file, line and value), 1 for an internal failure,",
             "130 when a study is interrupted.",
             ".SH SEE ALSO", "The README and docs/ of the symphong repository; the Python module: \\fBpython3 -c 'import symphong; help(symphong)'\\fR"]
    with open(out, "w") as f:
        f.write("\n".join(page) + "\n")


if __name__ == "__main__":
    main()
