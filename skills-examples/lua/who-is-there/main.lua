-- Who is there: counts the people in view and greets a new person, learning their face
-- after the user agrees. Shows marvin.vision.look and marvin.vision.enroll (API 1.2).

local function capitalize(words)
  return (words:gsub("(%a)(%w*)", function(first, rest) return first:upper() .. rest end))
end

-- The camera may be missing or unplugged: say so rather than fail.
local function look()
  local ok, seen = pcall(marvin.vision.look)
  if ok then return seen end
  marvin.log("camera: " .. tostring(seen), "warning")
  marvin.say("I can't see right now.")
  return nil
end

marvin.on("count", function()
  local seen = look()
  if not seen then return end
  local n = #seen.faces
  if n == 0 then
    marvin.say("I don't see anyone.")
  elseif n == 1 then
    marvin.say("I see one person.")
  else
    marvin.say("I see " .. n .. " people.")
  end
end)

marvin.on("meet", function(slots)
  local name = capitalize(slots.name)
  local seen = look()
  if not seen then return end
  if #seen.faces ~= 1 then
    marvin.say("I need to see " .. name .. " alone.")
    return
  end
  if seen.faces[1].name == name then
    marvin.say("Hello again, " .. name .. "!")
    return
  end
  local answer = marvin.ask("Hello " .. name .. "! May I remember your face?"):lower()
  if answer:sub(1, 3) ~= "yes" then
    marvin.say("All right, I won't.")
    return
  end
  marvin.vision.enroll(name, 5)
  marvin.say("Thank you, " .. name .. ". I'll know you next time.")
end)
