"""laserpeople.identity"""
