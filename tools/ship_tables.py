#!/usr/bin/env python3
"""Write the constant tables that ship with the package, computed from their definitions: the GGX energy tables
(python/restircl/upload/ggx_tables.npz, ggx_tables.py) and the glass tables (glass_tables.npz, glass_tables.py). Run
it after changing how a table is computed or its sizes; tests/upload/test_ggx_tables.py and test_glass_tables.py fail
while a shipped file differs from a fresh computation.

    python tools/ship_tables.py
"""

from __future__ import annotations

from restircl.upload import ggx_tables, glass_tables


def main() -> int:
    for tables in (ggx_tables, glass_tables):
        tables.write_shipped()
        print(f"wrote {tables.SHIPPED}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
