#!/usr/bin/env python3
"""Lists type names declared at namespace scope by more than one header of the product and the bench
(core, drone, localization, control, server, bench): each name should be one type. Exit 1 when one
is repeated. Usage: python3 scripts/type_names.py [ROOT]"""
import collections
import pathlib
import re
import sys

root = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else '.')
declared = collections.defaultdict(list)
for folder in ('core', 'drone', 'localization', 'control', 'server', 'bench'):
    for header in sorted((root / folder).rglob('*.hpp')):
        namespace = None
        for line in header.read_text().splitlines():
            if m := re.match(r'^namespace ([\w:]+) \{', line):
                namespace = m.group(1)
            elif m := re.match(r'^(?:class|struct|enum class|enum)\s+(\w+)\s*(?:final\s*)?[:{]', line):
                declared[m.group(1)].append(f'{namespace}::{m.group(1)} ({header.relative_to(root)})')
repeated = {name: where for name, where in declared.items() if len(where) > 1}
for name, where in sorted(repeated.items()):
    print(f'{name}: ' + ', '.join(where))
sys.exit(1 if repeated else 0)
