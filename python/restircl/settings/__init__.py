"""TODO settings"""
