from setuptools import setup

setup(
    name="r2_ext",
    version="0.0.1",
    packages=["r2_ext"],
    data_files=[("share/ament_index/resource_index/packages", ["resource/r2_ext"]),
                ("share/r2_ext", ["package.xml"])],
    entry_points={
        "launch.frontend.launch_extension": ["r2_ext = r2_ext"],
    },
)
