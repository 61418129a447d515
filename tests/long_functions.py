#!/usr/bin/python3
"""Functions longer than a limit in C++ sources, longest first.

Usage: tests/long_functions.py [--limit 80] FILE_OR_DIR...   (default: src)

A brace scan: comments, string and character literals are blanked first; a '{' whose text
before it ends in ')' (with const, noexcept, override, a trailing return type or a
constructor's initialiser list) opens a function body unless it is already inside one
(lambdas count towards their enclosing function). Lines are counted from the line of the
opening brace to that of the closing one, both included.
"""
import argparse
import pathlib
import re
import sys


def blank(src):
    """The source with comments and literals replaced by spaces (newlines kept)."""
    out, i, n = [], 0, len(src)
    while i < n:
        if src.startswith('//', i):
            j = src.find('\n', i)
            j = n if j < 0 else j
        elif src.startswith('/*', i):
            j = src.find('*/', i) + 2
        elif src[i] == '"' and i > 0 and src[i - 1] == 'R':
            m = re.match(r'"([^(]*)\(', src[i:])
            end = ')' + m.group(1) + '"'
            j = src.find(end, i) + len(end)
        elif src[i] in '"\'':
            j = i + 1
            while src[j] != src[i]:
                j += 2 if src[j] == '\\' else 1
            j += 1
        else:
            out.append(src[i])
            i += 1
            continue
        out.append(re.sub(r'[^\n]', ' ', src[i:j]))
        i = j
    return ''.join(out)


def functions(path):
    text = blank(path.read_text(encoding='utf-8'))
    found, stack, line = [], [], 1
    for k, ch in enumerate(text):
        if ch == '\n':
            line += 1
        elif ch == '{':
            before = text[max(0, k - 400):k].rstrip()
            in_function = any(kind == 'fn' for kind, _, _ in stack)
            is_function = (not re.search(r'(namespace|class|struct|union|enum)\b[^;{}()]*$', before) and
                           re.search(r'\)\s*(const|noexcept|override|final|->[^{};]*|:[^{};]*|\s)*$', before, re.S))
            if is_function and not in_function:
                names = re.findall(r'([~\w:]+)\s*\([^;{}]*$', before, re.S)
                stack.append(('fn', line, names[0] if names else '?'))
            else:
                stack.append(('block', line, ''))
        elif ch == '}' and stack:
            kind, first, name = stack.pop()
            if kind == 'fn':
                found.append((line - first + 1, str(path), first, name))
    return found


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument('--limit', type=int, default=80)
    ap.add_argument('paths', nargs='*', default=['src'])
    a = ap.parse_args()
    files = []
    for p in map(pathlib.Path, a.paths):
        files += sorted(q for q in p.rglob('*') if q.suffix in ('.cpp', '.hpp')) if p.is_dir() else [p]
    rows = sorted((f for p in files for f in functions(p) if f[0] > a.limit), reverse=True)
    for n, path, first, name in rows:
        print(f'{n:5d}  {path}:{first}  {name}')
    return 0


if __name__ == '__main__':
    sys.exit(main())
