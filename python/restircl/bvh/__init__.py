"""TODO bvh"""
