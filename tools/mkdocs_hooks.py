"""MkDocs hook: lets the pages keep the list style GitHub renders (a list right under its
lead-in line, sub-items indented by two spaces), which Python-Markdown would otherwise run into
the paragraph above or flatten. At build time it inserts the blank line before a list and
doubles a two-space sub-item indent to the four spaces Python-Markdown nests by."""
import re

LIST_ITEM = re.compile(r"^( *)([-*+]|\d+\.) ")


def normalise_lists(markdown):
    out, fence, prev = [], False, ""
    for line in markdown.split("\n"):
        if line.lstrip().startswith("```"):
            fence = not fence
        elif not fence:
            m = LIST_ITEM.match(line)
            if m:
                indent = len(m.group(1))
                if 0 < indent < 4:
                    line = " " * (2 * indent) + line[indent:]
                lead_in = prev.strip() and not prev.startswith(" ") and not LIST_ITEM.match(prev)
                if lead_in and not prev.lstrip().startswith(("|", "<!--")):
                    out.append("")
        out.append(line)
        prev = line
    return "\n".join(out)


def on_page_markdown(markdown, **kwargs):
    return normalise_lists(markdown)
