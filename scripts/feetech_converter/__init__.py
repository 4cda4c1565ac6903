"""The FEETECH model converter: reads the verbatim memory tables of ../shared/reference/feetech/
and writes models/feetech/<name>.json (docs/feetech.md "Models").

Modules, in the order a model goes through them:
- reference.py: the tables of one reference file (FEETECH's wiki table, the ST3215 spreadsheet,
  lerobot's table), parsed with the DYNAMIXEL converter's Markdown reader;
- decisions.py: every choice the sources leave open, each with the note written beside it;
- items.py: the items of one model from its wiki table and the decisions;
- builder.py: the model-level fields and the notes comparing the model with lerobot;
- cli.py: the command line (--check).
Standard library only.
"""
