"""The OpenCL plumbing every other package stands on: the device and its cached context (device.py), the program
built from opencl/ with feature flags (program.py), kernel launches by argument name (kernels.py), the numpy
mirrors of the shared structs (layouts.py) and the frame's scratch buffers (buffers.py)."""
