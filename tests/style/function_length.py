#!/usr/bin/env python3
"""function_length.py [--limit=N] FILES...: lists functions longer than N lines (default 120), found
by brace matching (comments and string literals skipped; blocks opened by namespace, class, struct,
enum, union or extern are scopes, not functions; lambdas count toward their function). Exits 1 when
it lists any: a long procedure is a short driver over named steps (docs/ARCHITECTURE.md)."""
import re, sys
limit = 120
args = sys.argv[1:]
if args and args[0].startswith('--limit='):
    limit = int(args[0].split('=')[1]); args = args[1:]
def strip(line, state):
    out = []; i = 0
    while i < len(line):
        if state['block']:
            j = line.find('*/', i)
            if j < 0: return ''.join(out)
            state['block'] = False; i = j + 2; continue
        c = line[i]
        if line.startswith('//', i): break
        if line.startswith('/*', i): state['block'] = True; i += 2; continue
        if c in '"\'':
            q = c; i += 1
            while i < len(line) and line[i] != q:
                i += 2 if line[i] == '\\' else 1
            i += 1; continue
        if line.startswith('R"(', i):
            j = line.find(')"', i); i = j + 2 if j >= 0 else len(line); continue
        out.append(c); i += 1
    return ''.join(out)
found = 0
for path in args:
    state = {'block': False}
    stack = []  # (kind, start_line, header)
    prev = ''
    for n, raw in enumerate(open(path, errors='replace'), 1):
        line = strip(raw.rstrip('\n'), state)
        for ch in line:
            if ch == '{':
                head = (prev + ' ' + line).strip()
                scope = re.search(r'\b(namespace|class|struct|enum|union|extern)\b[^;(]*$', line.split('{')[0]) or \
                        (line.strip() == '{' and re.search(r'\b(namespace|class|struct|enum)\b', prev))
                in_func = any(k == 'func' for k, _, _ in stack)
                kind = 'scope' if (scope and not in_func) else ('func' if not in_func else 'inner')
                stack.append((kind, n, raw.strip()))
            elif ch == '}':
                if stack:
                    kind, start, head = stack.pop()
                    if kind == 'func' and n - start + 1 > limit:
                        print(f'{path}:{start}: {n - start + 1} lines: {head[:90]}')
                        found += 1
        if line.strip(): prev = line
sys.exit(1 if found else 0)
