"""The converter's decisions, as data: everything the pages do not state, and the per-family,
per-model and per-item choices the code applies. Each entry carries the note that is written
into the model with it, and names its evidence.

- catalogue.py: which pages are converted; page name -> family, product group, variant.
- model_fields.py: model-level fields (firmware version, timing, protocols, baud tables,
  degrees per pulse, Indirect blocks, dual-axis modules).
- item_rules.py: item-level rules (power-on values for '-', signedness, accepted values,
  bounds, ranges widened to the factory value, MX(2.0) range donors).
- range_choices.py: ranges for items a page leaves open, each with its quoted evidence.
- motor_specs.py: motor figures for pages without a Specifications table.
- modbus.py: the firmware Modbus RTU needs, and the rows whose printed Modbus address is a misprint.
"""

# The e-Manual's include blocks, for the ones the offline reference did not copy.
EMANUAL_INCLUDES = "https://github.com/ROBOTIS-GIT/emanual/blob/master/_includes/en/dxl/"
