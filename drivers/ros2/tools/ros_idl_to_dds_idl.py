#!/usr/bin/env python3
"""Renames a ROS 2 message's IDL (as `rosidl translate --to idl` writes it) to the names
rmw_cyclonedds gives the type on the wire, so Cyclone's idlc generates a type every ROS 2 node
reads: `pkg::msg::Name` becomes `pkg::msg::dds_::Name_` (rmw_cyclonedds' type_name.cpp), and the
annotations idlc does not know (@verbatim comments, @default values) are dropped; they change
nothing on the wire. Each file gets an include guard.

usage: ros_idl_to_dds_idl.py IN.idl OUT.idl
"""
import pathlib
import re
import sys


def to_dds(text: str) -> str:
    # An annotation with its parenthesised arguments, strings inside them included.
    text = re.sub(r'@(verbatim|default|unit)\s*\((?:[^()"]|"(?:[^"\\]|\\.)*")*\)\s*', '', text)
    if '@' in text:
        raise ValueError('an annotation this tool does not know: ' + text[text.index('@'):][:40])
    # rosidl writes `module pkg {\n  module msg {\n ... \n  };\n};`: one more module inside.
    text, opened = re.subn(r'\bmodule msg \{', 'module msg { module dds_ {', text)
    text, closed = re.subn(r'\};\s*\};\s*$', '}; };\n};\n', text.rstrip() + '\n')
    if opened != 1 or closed != 1:
        raise ValueError('expected one `module msg` closed at the end of the file')
    text = re.sub(r'\bstruct (\w+) \{', r'struct \1_ {', text)
    return re.sub(r'\b(\w+)::msg::(\w+)\b', r'\1::msg::dds_::\2_', text)


def main() -> int:
    if len(sys.argv) != 3:
        print(__doc__.strip().splitlines()[-1], file=sys.stderr)
        return 2
    source, target = pathlib.Path(sys.argv[1]), pathlib.Path(sys.argv[2])
    try:
        text = to_dds(source.read_text())
    except (OSError, ValueError) as error:
        print(f'{source}: {error}', file=sys.stderr)
        return 2
    # A guard, as C headers have: a type reached by two includes (Gid through NodeEntitiesInfo and
    # directly) is declared once, and idlc refuses a typedef declared twice.
    guard = '_'.join(target.with_suffix('').parts[-3:]).upper() + '_IDL_'
    text = f'#ifndef {guard}\n#define {guard}\n{text}#endif\n'
    target.parent.mkdir(parents=True, exist_ok=True)
    target.write_text(text)
    return 0


if __name__ == '__main__':
    sys.exit(main())
