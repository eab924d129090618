// The login page: sends the password, then opens the page (the session is an HttpOnly
// cookie; the page asks /api/session for its CSRF token).
'use strict';
document.getElementById('login-form').addEventListener('submit', async (event) => {
  event.preventDefault();
  const message = document.getElementById('login-message');
  message.textContent = 'Logging in…';
  try {
    const response = await fetch('/api/login', {
      method: 'POST',
      headers: {'Content-Type': 'application/json'},
      body: JSON.stringify({password: document.getElementById('password').value}),
    });
    const body = await response.json();
    if (!response.ok) {
      message.textContent = body.error || ('Login failed (' + response.status + ')');
      return;
    }
    window.location.href = '/';
  } catch (e) {
    message.textContent = 'Marvin cannot be reached: ' + e.message;
  }
});
