"""Which reference pages become models (CONVERTED_PAGES), and what a page's name says about it:
its behaviour family, its e-Manual product group (which picks the Liquid branches of the
includes) and its variant (the family, or a product line within it where that decides something).

Adding a page: add its name to CONVERTED_PAGES; if no PAGE_RULES pattern matches it, add one.
"""

from __future__ import annotations

import re

V1_FAMILIES = {"ax", "rx", "ex", "mx1"}           # Protocol 1.0 control tables
P2_FAMILIES = {"x", "mx2", "p", "pro", "y"}       # Protocol 2.0 tables with 4-byte items


# The pages whose layouts this converter reads. The reference holds more (the rest of the ROBOTIS
# catalogue); they are named by --check and the summary as not converted, and are not models yet.
CONVERTED_PAGES = (
    "2xc430-w250",
    "2xl430-w250",
    "ax-12a",
    "ax-12w",
    "ax-18a",
    "dx-113",
    "dx-116",
    "dx-117",
    "ex-106+",
    "h42-20-s300-r",
    "h42-20-s300-ra",
    "h54-100-s500-r",
    "h54-100-s500-ra",
    "h54-200-s500-r",
    "h54-200-s500-ra",
    "l42-10-s300-r",
    "l54-30-s400-r",
    "l54-30-s500-r",
    "l54-50-s290-r",
    "l54-50-s500-r",
    "m42-10-s260-r",
    "m42-10-s260-ra",
    "m54-40-s250-r",
    "m54-40-s250-ra",
    "m54-60-s250-r",
    "m54-60-s250-ra",
    "mx-106",
    "mx-106-2",
    "mx-12w",
    "mx-28",
    "mx-28-2",
    "mx-64",
    "mx-64-2",
    "ph42-020-s300-r",
    "ph54-100-s500-r",
    "ph54-200-s500-r",
    "pm42-010-s260-r",
    "pm54-040-s250-r",
    "pm54-060-s250-r",
    "rh-p12-rn",
    "rh-p12-rna",
    "rx-10",
    "rx-24f",
    "rx-28",
    "rx-64",
    "xc330-m181",
    "xc330-m288",
    "xc330-t181",
    "xc330-t288",
    "xc430-t150bb",
    "xc430-t240bb",
    "xc430-w150",
    "xc430-w240",
    "xd430-t210",
    "xd430-t350",
    "xd540-t150",
    "xd540-t270",
    "xh430-v210",
    "xh430-v350",
    "xh430-w210",
    "xh430-w350",
    "xh540-v150",
    "xh540-v270",
    "xh540-w150",
    "xh540-w270",
    "xl-320",
    "xl330-m077",
    "xl330-m288",
    "xl430-w250",
    "xm335-t323",
    "xm430-w210",
    "xm430-w350",
    "xm540-w150",
    "xm540-w270",
    "xw430-t200",
    "xw430-t333",
    "xw540-h260",
    "xw540-t140",
    "xw540-t260",
    "ym070-210-a051-rh",
    "ym070-210-a099-rh",
    "ym070-210-b001-rh",
    "ym070-210-m001-rh",
    "ym070-210-r051-rh",
    "ym070-210-r099-rh",
    "ym080-230-a051-rh",
    "ym080-230-a099-rh",
    "ym080-230-b001-rh",
    "ym080-230-m001-rh",
    "ym080-230-r051-rh",
    "ym080-230-r099-rh",
)

# Page name (fullmatch) -> behaviour family (docs/model-format.md `family`) and the e-Manual's
# `page.product_group` (the front matter of the e-Manual page; ROBOTIS-GIT/docs pages carry none,
# so the group of their e-Manual original is used). The first pattern that matches wins.
PAGE_RULES = (
    (r"xl-320", "xl320", "dxl_xl320"),
    (r"xl330.*", "x", "xl330"),
    (r"xc330.*", "x", "xc330"),
    (r"xm335.*", "x", "xm335"),
    (r"2?x[lc]430.*", "x", "dxl_xl430"),
    (r"x[mhd]540.*", "x", "dxl_x540"),
    (r"xw540.*", "x", "dxl_xw540"),
    (r"xw430.*", "x", "dxl_xw430"),
    (r"x[mhd]430.*", "x", "dxl_x430"),
    (r"mx-.*-2", "mx2", "dxl_mx2"),
    (r"mx-.*", "mx1", "dxl_mx"),
    (r"ax-.*", "ax", "dxl_ax"),
    (r"rx-.*", "rx", "dxl_rx"),
    (r"ex-.*", "ex", "dxl_ex"),
    (r"p[hm]\d.*", "p", "dxl_p"),
    (r"[hml]\d\d-.*-ra", "pro_a", "dxl_pro_a"),
    (r"[hml]\d\d-.*-r", "pro", "dxl_pro"),
    (r"rh-p12-rna", "p", "rh_p12_rna"),
    (r"rh-p12-rn", "pro", "rh_p12_rn"),
    (r"dx-.*", "dx", "dxl_dx"),
    # DYNAMIXEL-Y: each page's front matter names its product group (dxl_y_m, dxl_y_b, dxl_y_r,
    # dxl_y_a), on which the Y includes branch (Bus Watchdog, Torque Enable: 'dxl_y_m').
    (r"ym\d+-\d+-m.*", "y", "dxl_y_m"),
    (r"ym\d+-\d+-b.*", "y", "dxl_y_b"),
    (r"ym\d+-\d+-r.*", "y", "dxl_y_r"),
    (r"ym\d+-\d+-a.*", "y", "dxl_y_a"),
)

# Product groups whose decisions differ from the rest of their family (firmware version,
# protocols, Protocol Type values, Indirect blocks): the X330 line of the X family.
VARIANTS = {"xl330": "x330", "xc330": "x330", "xm335": "x330"}


def classify(name: str) -> tuple[str, str]:
    """(family, product group) of the page `name`, from PAGE_RULES."""
    for pattern, family, group in PAGE_RULES:
        if re.fullmatch(pattern, name):
            return family, group
    raise SystemExit(f"convert_models: no family rule for page {name!r}")


# Families whose decisions fall back to another family's where they have no entry of their own:
# DX is the RX generation's servo (protocol1.md: 'DYNAMIXELs using Protocol 1.0 such as AX-12A, DX
# series'), PRO(A) runs the DYNAMIXEL-P firmware on PRO hardware (its page shows the P layout).
FAMILY_PARENTS = {"dx": "rx", "pro_a": "p"}


def variant_of(family: str, group: str) -> str:
    """The key of the per-variant decisions: VARIANTS[group], else the family."""
    return VARIANTS.get(group, family)


def lineage(family: str, group: str) -> tuple[str, ...]:
    """The keys a decision table is asked for, most specific first: the variant (if it is not the
    family), the family, then its parents (FAMILY_PARENTS)."""
    keys = [variant_of(family, group), family]
    while keys[-1] in FAMILY_PARENTS:
        keys.append(FAMILY_PARENTS[keys[-1]])
    return tuple(dict.fromkeys(keys))
