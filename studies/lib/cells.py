"""How the studies write a number into a cell of their Markdown tables."""


def fmt(v, digits=3):
    """v to `digits` significant digits; "-" where there is no value."""
    return "-" if v is None else "%.*g" % (digits, v)
