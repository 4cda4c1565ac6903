"""Which reference pages become models, and what a page's name says about it: its behaviour
family and its e-Manual product group. Adding a page starts here (CONVERTED_PAGES)."""

from __future__ import annotations

V1_FAMILIES = {"ax", "rx", "ex", "mx1"}           # Protocol 1.0 control tables
P2_FAMILIES = {"x", "mx2", "p", "pro"}            # Protocol 2.0 tables with 4-byte items
X330 = {"xl330-m288", "xl330-m077", "xc330-t288"}  # product groups xl330 / xc330


# The pages whose layouts this converter reads. The reference holds more (the rest of the ROBOTIS
# catalogue); they are named by --check and the summary as not converted, and are not models yet.
CONVERTED_PAGES = (
    "2xl430-w250",
    "ax-12a",
    "ax-12w",
    "ax-18a",
    "ex-106+",
    "h54-200-s500-r",
    "mx-106",
    "mx-106-2",
    "mx-28",
    "mx-28-2",
    "mx-64",
    "mx-64-2",
    "ph54-200-s500-r",
    "rx-24f",
    "rx-28",
    "rx-64",
    "xc330-t288",
    "xc430-w150",
    "xc430-w240",
    "xh430-w210",
    "xh430-w350",
    "xh540-w150",
    "xh540-w270",
    "xl-320",
    "xl330-m077",
    "xl330-m288",
    "xl430-w250",
    "xm430-w210",
    "xm430-w350",
    "xm540-w150",
    "xm540-w270",
    "xw540-t260",
)


def family_of(name: str) -> str:
    """Behaviour family from the page file name (docs/model-format.md `family`)."""
    if name == "xl-320":
        return "xl320"
    if name.startswith(("x", "2x")):
        return "x"
    if name.startswith("mx-"):
        return "mx2" if name.endswith("-2") else "mx1"
    if name.startswith("ax-"):
        return "ax"
    if name.startswith("rx-"):
        return "rx"
    if name.startswith("ex-"):
        return "ex"
    if name.startswith("ph"):
        return "p"
    if name.startswith("h54"):
        return "pro"
    raise SystemExit(f"convert_models: no family rule for page {name!r}")


def product_group(name: str, family: str) -> str:
    """The e-Manual `page.product_group`, used to pick Liquid branches of the includes."""
    if name.startswith("xl330"):
        return "xl330"
    if name.startswith("xc330"):
        return "xc330"
    return {"x": "dxl_x430", "mx2": "dxl_mx2", "mx1": "dxl_mx", "ax": "dxl_ax", "rx": "dxl_rx",
            "ex": "dxl_ex", "xl320": "dxl_xl320", "p": "dxl_p", "pro": "dxl_pro"}[family]
