"""TODO environment"""
