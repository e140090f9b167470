"""Print per-tier and total test counts from pytest junit XML files."""
import os
import sys
import xml.etree.ElementTree as ET

tp = tf = ts = 0
for path in sys.argv[1:]:
    root = ET.parse(path).getroot()
    suites = [root] if root.tag == "testsuite" else root.findall("testsuite")
    n = sum(int(s.get("tests", 0)) for s in suites)
    f = sum(int(s.get("failures", 0)) + int(s.get("errors", 0)) for s in suites)
    s_ = sum(int(s.get("skipped", 0)) for s in suites)
    p = n - f - s_
    tp, tf, ts = tp + p, tf + f, ts + s_
    print(f"tier {os.path.basename(path)[:-4]}: {p} passed, {f} failed, {s_} skipped")
print(f"total: {tp} passed, {tf} failed" + (f", {ts} skipped" if ts else ""))
sys.exit(1 if tf or tp == 0 else 0)
