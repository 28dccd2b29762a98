"""icerubble: 2D FEM-DEM simulation of punch-through tests on ice rubble.

Polojärvi & Tuhkuri (2013). The compiled engine lives in ``icerubble._engine``
(CST elements, potential contact, freeze-bond node splitting) and the
freeze-bond law in ``icerubble._cohesive_law``; build them with ``make build``.
"""
__version__ = "0.1.0"
