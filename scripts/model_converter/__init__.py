"""The model converter behind scripts/convert_models.py: ROBOTIS e-Manual control-table pages in,
dxlemu model files out. One job per module, in the order a page goes through them:

- reference.py: the files of ../shared/reference (pages, includes, models.tsv).
- markdown.py: cells, numbers, units, bit rates, pipe tables, Liquid product_group branches.
- page.py: a page's EEPROM/RAM tables as rows ('…' series expanded) and its description
  sections; spec_table.py: its Specifications table.
- ranges.py: what a Range cell says, item widths, range choices and their evidence check.
- items.py: Item (one item on its way to JSON) and Draft (one page on its way to a model).
- item_builder.py: the item passes in order; item_ranges.py: where each item's range comes from.
- builder.py: the model-level fields and notes; motion.py: the motion block.
- modbus_map.py: the Modbus Address column of a model that lists "modbus", checked row by row;
  its 'N/A' items marked absent_in modbus.
- validation.py: the format's rules, the row-by-row cross-check, the --check comparison.
- cli.py: the command line.
- decisions/: everything the converter decides, as data (see its __init__.py).
"""
