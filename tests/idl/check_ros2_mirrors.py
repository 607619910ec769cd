#!/usr/bin/python3
"""idl/hadal_msgs.idl and its ROS 2 mirror idl/ros2/hadal_msgs/msg/*.msg describe the same messages: every
struct has a .msg with the same fields (names, types, order) and its <Name>_Constants the same constants,
and every .msg has a struct. A field added to one and not the other would build in one world and break the
other's wire layout. usage: check_ros2_mirrors.py REPO_ROOT"""

import os
import re
import sys

IDL_TO_MSG = {"double": "float64", "float": "float32", "boolean": "bool", "octet": "byte", "string": "string",
              "int8": "int8", "uint8": "uint8", "int16": "int16", "uint16": "uint16", "int32": "int32",
              "uint32": "uint32", "int64": "int64", "uint64": "uint64"}


def msg_type(idl_type):
    """The .msg spelling of an IDL member type: sequence<T> -> T[], pkg::msg::T -> pkg/T (a fixed array, T name[N],
    is T[N]: idl_messages adds the size)."""
    sequence = re.fullmatch(r"sequence<\s*(.+?)\s*>", idl_type)
    if sequence:
        return msg_type(sequence.group(1)) + "[]"
    if "::" in idl_type:
        package, _, name = idl_type.split("::")
        return f"{package}/{name}"
    return IDL_TO_MSG[idl_type]


def idl_messages(text):
    text = re.sub(r"//[^\n]*", "", text)
    structs, constants = {}, {}
    for name, body in re.findall(r"struct\s+(\w+)\s*\{(.*?)\};", text, re.S):
        structs[name] = [(msg_type(t.strip()) + (f"[{size}]" if size else ""), n)
                         for t, n, size in re.findall(r"([\w:<>\s]+?)\s+(\w+)\s*(?:\[(\d+)\])?\s*;", body)]
    for name, body in re.findall(r"module\s+(\w+)_Constants\s*\{(.*?)\};", text, re.S):
        constants[name] = [(msg_type(t), n, v) for t, n, v in re.findall(r"const\s+(\w+)\s+(\w+)\s*=\s*([^;]+);", body)]
    return structs, constants


def msg_fields(text):
    fields, constants = [], []
    for line in text.splitlines():
        line = line.split("#")[0].strip()
        if not line:
            continue
        m = re.fullmatch(r"(\S+)\s+(\w+)\s*=\s*(\S+)", line)
        if m:
            constants.append((m.group(1), m.group(2), m.group(3)))
            continue
        kind, name = line.split()[:2]
        fields.append((kind, name))
    return fields, constants


def main(root):
    structs, constants = idl_messages(open(os.path.join(root, "idl/hadal_msgs.idl")).read())
    msg_dir = os.path.join(root, "idl/ros2/hadal_msgs/msg")
    problems = []
    msgs = {f[:-4] for f in os.listdir(msg_dir) if f.endswith(".msg")}
    for name in sorted(set(structs) | msgs):
        if name not in msgs:
            problems.append(f"{name}: in idl/hadal_msgs.idl but no idl/ros2/hadal_msgs/msg/{name}.msg")
            continue
        if name not in structs:
            problems.append(f"{name}.msg has no struct in idl/hadal_msgs.idl")
            continue
        fields, msg_constants = msg_fields(open(os.path.join(msg_dir, name + ".msg")).read())
        if fields != structs[name]:
            problems.append(f"{name}: fields differ\n  idl: {structs[name]}\n  msg: {fields}")
        if sorted(msg_constants) != sorted(constants.get(name, [])):
            problems.append(f"{name}: constants differ\n  idl: {constants.get(name, [])}\n  msg: {msg_constants}")
    for problem in problems:
        print("FAIL:", problem, file=sys.stderr)
    if not problems:
        print(f"ok: {len(structs)} messages, fields and constants alike in the IDL and the .msg files")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1]))
