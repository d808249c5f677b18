"""Gather each subject's numbers into figures/numbers.json and its markdown table (shown in the README)."""
import json
import sys
from pathlib import Path

sys.stderr = open(snakemake.log[0], "w", buffering=1)

from noslipsim.plot import numbers_markdown

numbers = {Path(p).stem: json.loads(Path(p).read_text(encoding="utf-8")) for p in snakemake.input}
table = numbers_markdown(numbers)  # validates every record
Path(snakemake.output.json).write_text(json.dumps(numbers, indent=1, ensure_ascii=False) + "\n", encoding="utf-8")
Path(snakemake.output.table).write_text(table, encoding="utf-8")
