"""Not a launch file: the server leaves ordinary Python alone."""


def frame(name):
    return name + '_link'
