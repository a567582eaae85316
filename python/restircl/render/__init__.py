"""TODO render"""
