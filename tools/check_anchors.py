"""Every link of a built MkDocs site to a page's #anchor must name an id that page has
(mkdocs 1.4 checks the pages of links, not their anchors).
usage: check_anchors.py SITE_DIR"""
import html.parser
import pathlib
import sys
import urllib.parse


class Page(html.parser.HTMLParser):
    def __init__(self):
        super().__init__()
        self.ids, self.links = set(), []

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if "id" in a:
            self.ids.add(a["id"])
        if tag == "a" and a.get("href") and "#" in a["href"] and "://" not in a["href"]:
            self.links.append(a["href"])


def main():
    site = pathlib.Path(sys.argv[1])
    pages = {}
    for f in site.rglob("*.html"):
        if "mathjax" in f.parts:
            continue
        p = Page()
        p.feed(f.read_text(errors="replace"))
        pages[f.resolve()] = p
    broken = []
    for f, p in pages.items():
        for href in p.links:
            path, _, anchor = href.partition("#")
            target = (f.parent / urllib.parse.unquote(path)).resolve() if path else f
            anchor = urllib.parse.unquote(anchor)
            if not anchor or target not in pages:
                continue
            if anchor not in pages[target].ids:
                broken.append(f"{f.relative_to(site.resolve())}: {href}")
    for b in broken:
        print("broken anchor:", b, file=sys.stderr)
    return 1 if broken else 0


if __name__ == "__main__":
    sys.exit(main())
