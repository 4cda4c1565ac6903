"""Converts the e-Manual control-table pages into dxlemu model files (scripts/convert_models.py)."""
