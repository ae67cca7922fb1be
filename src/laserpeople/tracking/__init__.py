"""laserpeople.tracking"""
