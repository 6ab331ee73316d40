#!/usr/bin/env python3
"""Replace the generated part of a Markdown file.

usage: update_results.py GENERATED_MD TARGET_MD

The text of GENERATED_MD goes between the lines
  <!-- BEGIN GENERATED: scripts/evaluate.sh -->
  <!-- END GENERATED: scripts/evaluate.sh -->
of TARGET_MD (appended with both markers when they are missing); the rest of TARGET_MD is kept.
"""
import os
import sys

BEGIN = "<!-- BEGIN GENERATED: scripts/evaluate.sh -->"
END = "<!-- END GENERATED: scripts/evaluate.sh -->"


def main(argv):
    if len(argv) != 3:
        sys.stderr.write(__doc__)
        return 2
    with open(argv[1]) as f:
        generated = f.read().strip("\n")
    text = ""
    if os.path.exists(argv[2]):
        with open(argv[2]) as f:
            text = f.read()
    block = "%s\n%s\n%s" % (BEGIN, generated, END)
    if BEGIN in text and END in text and text.index(BEGIN) < text.index(END):
        head = text[:text.index(BEGIN)]
        tail = text[text.index(END) + len(END):]
        text = head + block + tail
    else:
        if text and not text.endswith("\n"):
            text += "\n"
        text += "\n" + block + "\n"
    with open(argv[2], "w") as f:
        f.write(text)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
