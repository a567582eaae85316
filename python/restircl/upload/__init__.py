"""TODO upload"""
