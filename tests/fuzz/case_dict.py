"""A libFuzzer dictionary of the field names, enum values and punctuation of proto/case.proto.
Usage: case_dict.py CASE_PROTO OUT_DICT"""
import re
import sys

text = open(sys.argv[1]).read()
words = set(re.findall(r"^\s*(?:optional|required|repeated)\s+\w+\s+(\w+)\s*=", text, re.M))
words |= set(re.findall(r"^\s*([A-Z][A-Z0-9_]+)\s*=", text, re.M))
words |= set(re.findall(r'default\s*=\s*"([^"]*)"', text))
tokens = sorted('"%s"' % w for w in words) + ['"{"', '"}"', '":"', '"\\""', '"nan"', '"inf"', '"-inf"',
                                              '"1e400"', '"1e-300"', '"2147483647"', '"-1"', '"0"']
with open(sys.argv[2], "w") as out:
    out.write("\n".join(tokens) + "\n")
