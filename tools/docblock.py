"""Writes generated text into a document between two markers,
<!-- NAME: begin --> and <!-- NAME: end -->, leaving the rest as it is.
Used by the scripts that write results into docs/ (tools/*_results.py,
tools/*_figures.py)."""
import sys


def replace_block(path, name, lines):
    begin, end = "<!-- %s: begin -->" % name, "<!-- %s: end -->" % name
    with open(path) as f:
        text = f.read()
    if begin not in text or end not in text:
        sys.exit("%s has no %s ... %s block" % (path, begin, end))
    head, rest = text.split(begin, 1)
    _, tail = rest.split(end, 1)
    with open(path, "w") as f:
        f.write(head + "\n".join([begin] + list(lines) + [end]) + tail)
